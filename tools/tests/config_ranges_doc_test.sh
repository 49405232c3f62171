#!/bin/sh
# A document's "Valid ranges" table must list exactly the ranges the code checks
# (`orthosonar <command> --ranges`), key by key.
# Usage: config_ranges_doc_test.sh ORTHOSONAR DOC_MD OUT_DIR [COMMAND [HEADING]]
#   COMMAND defaults to "config" (docs/CONFIG.md, the run configuration); "simulate" with
#   HEADING "Valid ranges of the simulator configuration" checks docs/SCENES.md.
set -e
cli=$1; doc=$2; out=$3; command=${4:-config}; heading=${5:-Valid ranges}
rm -rf "$out"; mkdir -p "$out"
"$cli" "$command" --ranges > "$out/code.tsv"
test -s "$out/code.tsv"
# Rows "| `key` | range |" after the heading "## $heading" (up to the next "## ").
awk -v h="## $heading" '$0 == h { f = 1; next } /^## / { f = 0 } f && /^\| `/' "$doc" |
  sed -e 's/^| `\([^`]*\)` | \(.*\) |$/\1\t\2/' -e 's/\\|/|/g' > "$out/doc.tsv"
if ! cmp -s "$out/code.tsv" "$out/doc.tsv"; then
  echo "$doc '$heading' differs from 'orthosonar $command --ranges':"
  diff "$out/code.tsv" "$out/doc.tsv" || true
  exit 1
fi
echo "$doc lists the ranges of all $(wc -l < "$out/code.tsv") keys"
