"""swarmform's launcher and viewer: `scripts/swarm` runs this package with Debian's /usr/bin/python3.

Modules, one job each:
  cli        the command line (`swarm run|demo|kill|replay|view|export|report|sweep|plot`), argument checks, dispatch
  places     where the programs, data, runs and commit are: the source tree, or an installed prefix
  launcher   starts the world and the robot agents, shows progress, cleans up every process
  agent_start  the run's agents started a slice at a time from the launcher's loop
  child_death  children that die with the process that started them (PR_SET_PDEATHSIG, the fork race closed)
  hosts      --hosts K / --link: emulated hosts as network namespaces on a bridge, shaped links, their cleanup
  recording  reads a run directory back (world.json, robots.csv, readings.csv, events.jsonl, summary.json)
  geometry   formation centre and shape error (rigid fit), from the recording
  scene      draws the arena and the robots at one tick (shared by the snapshots and the animation)
  pictures   the paper's figures (snapshots, trajectories, residual force, shape error)
  animation  the whole run as MP4 and GIF, through ffmpeg
  report     summary.json as a readable table
  export     `swarm export --mcap`: a run as an MCAP file Foxglove opens
  sweep      `swarm sweep`: a grid of in-process runs on every core, judged; sweep.csv and sweep.json
  sweep_journal  a sweep folder read back (sweep_args.json, runs.jsonl) for --shard, --merge and --resume
  sweep_cluster  --cluster: the runs on a Dask scheduler's workers
  sweep_plots    `swarm plot`: the success heat map, a metric's median and interval, failures by reason
"""
