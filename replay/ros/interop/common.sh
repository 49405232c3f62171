# Sourced by roundtrip.sh, ros2_typescript.sh and gyro_interop.sh (needs $cli, $scene,
# $seconds, fail(); $sim_args, if set, adds simulate options such as --sim-config FILE):
# simulates the mission, writes its effective configuration to cfg.yaml and defines
# run <fixture> <out dir> (a replay with that configuration and the scene's mesh) and
# same_maps <out dir> <label> (the round trip's maps and trajectories are the original's).
# shellcheck disable=SC2086  # $sim_args: options, split on purpose
"$cli" simulate --scene "$scene" --duration "$seconds" --resolution reduced --threads 1 -q -o orig.mcap \
  --export-mesh scene.ply ${sim_args:-} || fail "simulate"
# The original's effective configuration (its extrinsics and mission start included):
# a bag has no scene, so the start pose comes from the run configuration.
"$cli" config --fixture orig.mcap >cfg.yaml || fail "config"
run() {  # run <fixture> <out dir>
  "$cli" replay "$1" --config cfg.yaml --mesh scene.ply -q -o "$2" >"$2.digest" 2>"$2.err" \
    || fail "replay $1: $(cat "$2.err")"
}
same_maps() {  # same_maps <out dir> <label>
  for key in fusion/map submap/map keyframes factors; do
    a=$(grep "\"$key\"" out_orig/digest.json)
    b=$(grep "\"$key\"" "$1/digest.json")
    [ -n "$a" ] && [ "$a" = "$b" ] || fail "$2: $key differs: original $a, round trip $b"
  done
  for f in traj_dr.tum traj_slam.tum fusion/map.pcd submap/map.pcd; do
    cmp -s "out_orig/$f" "$1/$f" || fail "$2: $f differs from the original's"
  done
  echo "$2: maps and trajectories identical to the original's"
}
