#!/bin/sh
# docs/CONFIG.md's first YAML block (every key at its default) must load and give exactly
# the built-in defaults, field by field, so the page cannot drift from the code unnoticed.
# Usage: config_doc_test.sh ORTHOSONAR CONFIG_MD OUT_DIR
set -e
cli=$1; doc=$2; out=$3
rm -rf "$out"; mkdir -p "$out"
awk '/^```yaml$/ { n++; if (n == 1) { f = 1; next } } /^```$/ { f = 0 } f' "$doc" > "$out/doc.yaml"
test -s "$out/doc.yaml"
"$cli" config > "$out/defaults.json"
"$cli" config --config "$out/doc.yaml" > "$out/documented.json"
test -s "$out/defaults.json"
if ! cmp -s "$out/defaults.json" "$out/documented.json"; then
  echo "docs/CONFIG.md does not match the built-in defaults:"
  diff "$out/defaults.json" "$out/documented.json" || true
  exit 1
fi
echo "docs/CONFIG.md matches the built-in defaults ($(wc -l < "$out/defaults.json") lines)"
