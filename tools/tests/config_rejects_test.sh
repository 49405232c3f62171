#!/bin/sh
# Bad configuration values give a clear error naming the key and a non-zero exit, never a
# silently wrong run. Usage: config_rejects_test.sh ORTHOSONAR OUT_DIR
cli=$1; out=$2
rm -rf "$out"; mkdir -p "$out"
check() {  # check 'yaml' 'expected message fragment'
  printf '%s\n' "$1" > "$out/c.yaml"
  if "$cli" config --config "$out/c.yaml" > "$out/stdout" 2> "$out/stderr"; then
    echo "accepted: $1"; exit 1
  fi
  grep -q "$2" "$out/stderr" || { echo "no '$2' in:"; cat "$out/stderr"; exit 1; }
  echo "rejected as expected: $1"
}
check 'dr: {attitude_filter_tau_s: -1}' "dr.attitude_filter_tau_s"
check 'dr: {attitude_filter_tau_s: .nan}' "dr.attitude_filter_tau_s"
check 'dr: {attitude_filter_max_gap_s: 0}' "dr.attitude_filter_max_gap_s"
check 'mapping: {voxel_m: 0}' "mapping.voxel_m"
check 'threads: 0' "threads"
# and a good value passes
printf 'dr: {attitude_filter_tau_s: 0}\n' > "$out/ok.yaml"
"$cli" config --config "$out/ok.yaml" > /dev/null
