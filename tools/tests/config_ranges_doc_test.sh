#!/bin/sh
# docs/CONFIG.md's "Valid ranges" table must list exactly the ranges the code checks
# (`orthosonar config --ranges`), key by key. Usage: config_ranges_doc_test.sh ORTHOSONAR CONFIG_MD OUT_DIR
set -e
cli=$1; doc=$2; out=$3
rm -rf "$out"; mkdir -p "$out"
"$cli" config --ranges > "$out/code.tsv"
test -s "$out/code.tsv"
# Rows "| `key` | range |" after the heading "## Valid ranges".
awk '/^## Valid ranges/ { f = 1; next } /^## / { f = 0 } f && /^\| `/' "$doc" |
  sed -e 's/^| `\([^`]*\)` | \(.*\) |$/\1\t\2/' -e 's/\\|/|/g' > "$out/doc.tsv"
if ! cmp -s "$out/code.tsv" "$out/doc.tsv"; then
  echo "docs/CONFIG.md 'Valid ranges' differs from 'orthosonar config --ranges':"
  diff "$out/code.tsv" "$out/doc.tsv" || true
  exit 1
fi
echo "docs/CONFIG.md lists the ranges of all $(wc -l < "$out/code.tsv") keys"
