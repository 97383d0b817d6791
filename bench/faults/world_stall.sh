#!/bin/bash
# bench/faults/world_stall.sh BUILD_DIR DOMAIN OUT_DIR: the world SIGSTOPped for 3 s in the middle of a run of
# 8 random walkers (tests/integration/random_walk_8.yaml), then SIGCONTed; prints the deaths and who was alive at
# the end (docs/faults.md). TICKS (default 15000), MODE (lockstep or realtime), STALL_S (the stop, default 3)
# and WORLD_PID=1 (the agents get --world-pid, as swarm run starts them) from the environment. Every process
# it starts is killed by pid at the end; every wait has a deadline.
set -u
case "${1:-}" in -h|--help|"") sed -n '2,5s/^# \{0,1\}//p' "$0"; exit 0 ;; esac
B=$1 D=$2 O=$3
root="$(cd "$(dirname "$0")/../.." && pwd)"
rm -rf "$O" && mkdir -p "$O"
"$B/world_server/world_server" --scenario "$root/tests/integration/random_walk_8.yaml" --out "$O/run" --domain "$D" \
  --max-ticks "${TICKS:-15000}" ${MODE:+--mode "$MODE"} --connect-timeout 30 > "$O/world.out" 2> "$O/world.err" &
W=$!
P=()
for i in 0 1 2 3 4 5 6 7; do
  "$B/robot_agent/robot_agent" --id "$i" --domain "$D" --timeout 30 ${WORLD_PID:+--world-pid "$W"} \
    > "$O/agent$i.out" 2> "$O/agent$i.err" &
  P+=($!)
done
for _ in $(seq 1 300); do grep -q "progress tick" "$O/world.out" && break; sleep 0.1; done
kill -STOP "$W"; sleep "${STALL_S:-3}"; kill -CONT "$W"
for _ in $(seq 1 1200); do kill -0 "$W" 2>/dev/null || break; sleep 0.1; done
kill -9 "$W" "${P[@]}" 2>/dev/null; wait 2>/dev/null
python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print('deaths', len(s['deaths']), 'alive_at_end', s['alive_at_end'], 'ticks', s['ticks'])" "$O/run/summary.json"
