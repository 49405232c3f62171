#!/usr/bin/env bash
# libtorch is loaded on demand (core/inference/torch_backend.hpp, docs/ARCHITECTURE.md):
#  1. `simulate` and `replay` (fusion, slam) never load libtorch; `selfcheck` (the torch pins)
#     does, through liborthosonar_torch.so;
#  2. the fixture's zstd level changes its bytes, never its events: replay digests agree;
#  3. with the module missing, a system that needs the classifier exits 2 naming the module
#     and where it looked.
# Usage: torch_on_demand_test.sh ORTHOSONAR WORK_DIR
set -euo pipefail
exe=$(realpath "$1") work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
loaded() { LD_DEBUG=files "$@" 2>&1 >/dev/null | grep -c 'file=libtorch_cpu\.so.*generating link map' || true; }

echo "== 1. which subcommands load libtorch"
test "$(loaded "$exe" simulate --scene harbor --duration 4 --resolution reduced -q -o a.mcap)" = 0 ||
  fail "simulate loaded libtorch"
test "$(loaded "$exe" replay a.mcap -q --systems fusion,slam -o r_a)" = 0 || fail "replay loaded libtorch"
test "$(loaded "$exe" selfcheck)" != 0 || fail "selfcheck did not load libtorch (the pins were not measured)"
"$exe" selfcheck | grep -q "selfcheck: ok" || fail "selfcheck failed"

echo "== 2. zstd level: other bytes, same events"
"$exe" simulate --scene harbor --duration 4 --resolution reduced -q --zstd-level 19 -o b.mcap
cmp -s a.mcap b.mcap && fail "zstd levels 1 and 19 wrote the same bytes"
da=$("$exe" replay a.mcap -q --systems fusion -o ra | tail -n 1)
db=$("$exe" replay b.mcap -q --systems fusion -o rb | tail -n 1)
test -n "$da" && test "$da" = "$db" || fail "digests differ: '$da' vs '$db'"
if "$exe" simulate --scene harbor --duration 1 -q --zstd-level 0 -o c.mcap 2>c.err; then fail "--zstd-level 0 accepted"; fi

echo "== 3. module missing"
echo not-a-model > m.pt
set +e
ORTHOSONAR_TORCH_MODULE=$work/nowhere.so "$exe" replay a.mcap -q --systems inference --model m.pt -o r_m 2>err.txt
rc=$?
set -e
test "$rc" = 2 || fail "exit $rc, expected 2: $(cat err.txt)"
grep -q "liborthosonar_torch.so" err.txt && grep -q "nowhere.so: not found" err.txt || fail "message: $(cat err.txt)"
echo "ok"
