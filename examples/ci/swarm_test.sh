#!/bin/sh
# A swarm as a CI test: six robots of a behaviour of our own (a Python program over --exec), two of them killed
# mid-run, and what must hold at the end. Run from the swarmform checkout; exit 0 = pass.
set -eu
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT INT TERM  # cleanup, pass or fail

# The deadline: `timeout` sends SIGTERM after 600 s (swarm then stops the world and every agent, exit 130) and
# SIGKILL 30 s later if that hangs (every process swarm started dies with it: PR_SET_PDEATHSIG).
timeout -k 30 600 scripts/swarm run \
  --scenario examples/agents/aggregation.yaml \
  --exec 'python3 examples/agents/aggregation.py' \
  --max-ticks 400 --kill 1@100 --kill 4@200 \
  --no-pictures --out "$out/run" \
  --expect 'deaths == 2' \
  --expect 'alive_at_end == 4' \
  --expect 'collisions_robot_robot <= 5' \
  --expect 'command_verdicts == 0'
echo "swarm test passed"
