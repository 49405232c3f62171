#!/usr/bin/env bash
# Builds a temporary repository whose "map" changes at a known commit (an injected
# regression among unrelated commits) and checks that tools/bisect-maps names it, and
# that the user's working tree (a dirty file) is left untouched.
set -euo pipefail
script="$1"
out_root="${ORTHOSONAR_TEST_OUT:-$(mktemp -d)}"
repo="$out_root/bisect_repo"
rm -rf "$repo"; mkdir -p "$repo"
cd "$repo"
git init -q -b main
git config user.email t@example.invalid; git config user.name test
cat > run.sh <<'R'
#!/usr/bin/env bash
# The "pipeline": the digest of its map parameters.
echo "digest: $(sha256sum params.txt | cut -c1-64)"
R
chmod +x run.sh
echo "voxel 0.1" > params.txt; echo 0 > notes.txt
git add -A; git commit -qm "c0 baseline"
for i in 1 2 3; do echo "$i" >> notes.txt; git commit -qam "c$i unrelated"; done
echo "voxel 0.2" > params.txt; git commit -qam "c4 injected regression"
regression=$(git rev-parse HEAD)
for i in 5 6 7; do echo "$i" >> notes.txt; git commit -qam "c$i unrelated"; done
echo "dirty" >> notes.txt   # the user's uncommitted work must survive
good=$(git rev-list --max-parents=0 HEAD)

out=$("$script" --repo "$repo" --build-cmd 'true' --run-cmd './run.sh' "$good" main scenario)
echo "$out"
grep -q "^first changed commit: $regression c4 injected regression$" <<<"$out" || { echo "FAIL: wrong commit named"; exit 1; }
grep -q "dirty" notes.txt || { echo "FAIL: working tree changed"; exit 1; }
[[ "$(git rev-parse --abbrev-ref HEAD)" == main ]] || { echo "FAIL: branch changed"; exit 1; }
[[ -z "$(git worktree list | sed -n 2p)" ]] || { echo "FAIL: worktree left behind"; exit 1; }

# A build failure in the middle is skipped, not blamed.
git stash -q
git checkout -q -b broken "$good"
for i in 1 2; do echo "$i" >> notes.txt; git commit -qam "b$i unrelated"; done
echo "voxel 0.3" > params.txt; git commit -qam "b3 regression"
reg2=$(git rev-parse HEAD)
echo "x" > BROKEN; git add BROKEN; git commit -qm "b4 breaks the build"
git rm -q BROKEN; git commit -qm "b5 fixes the build"
out=$("$script" --repo "$repo" --build-cmd '! test -e BROKEN' --run-cmd './run.sh' "$good" broken scenario)
echo "$out"
grep -q "^first changed commit: $reg2 " <<<"$out" || { echo "FAIL: wrong commit with a build break"; exit 1; }

# Same digest at both ends: exit 1 with a clear message.
set +e
"$script" --repo "$repo" --build-cmd true --run-cmd './run.sh' "$good" "$good" scenario
rc=$?
set -e
[[ $rc -eq 1 ]] || { echo "FAIL: expected exit 1 when nothing changed, got $rc"; exit 1; }
echo "bisect-maps test: ok"
