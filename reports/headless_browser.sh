#!/bin/sh
# report.html opened in a headless browser with no network (issue 38): every image decodes.
# A short simulated mission is replayed and reported; the report is copied with a script
# appended that, once the page has loaded, counts the images the browser decoded
# (complete, naturalWidth > 0) and writes the count into the page; Chromium's headless
# shell dumps the DOM after load. The page itself has no scripts and no external references.
# usage: headless_browser.sh ORTHOSONAR WORK_DIR
set -eu
bin=$1
work=$2
browser=$(command -v chromium-headless-shell || true)
if [ -z "$browser" ]; then
  echo "headless_browser.sh: chromium-headless-shell not found (tools/install-deps installs it)" >&2
  exit 1
fi
rm -rf "$work"
mkdir -p "$work"
"$bin" simulate --scene harbor --duration 20 --resolution reduced -q -o "$work/m.mcap" >/dev/null
"$bin" replay "$work/m.mcap" -q -o "$work/run" >/dev/null
"$bin" report "$work/run" -o "$work/report" >/dev/null
html="$work/report/report.html"
size=$(wc -c < "$html")
echo "report.html: $size bytes"
# No src= or href= to anything but an embedded image.
if grep -o -E '(src|href)="[^"]*"' "$html" | grep -v -E '^(src|href)="data:image/(png|jpeg);base64,' ; then
  echo "FAIL: report.html references the files or URLs above" >&2
  exit 1
fi
expected=$(grep -o 'data-file="' "$html" | wc -l)
if [ "$expected" -lt 5 ]; then
  echo "FAIL: only $expected figures in the report" >&2
  exit 1
fi
check="$work/check.html"
sed 's|</body>|<script>window.addEventListener("load",function(){var i=Array.from(document.images);var ok=i.filter(function(x){return x.complete\&\&x.naturalWidth>0;}).length;document.body.setAttribute("data-check","images "+i.length+" decoded "+ok);});</script></body>|' "$html" > "$check"
dom=$("$browser" --no-sandbox --disable-gpu --no-proxy-server --host-resolver-rules="MAP * ~NOTFOUND" \
        --virtual-time-budget=20000 --dump-dom "file://$check" 2>"$work/browser.log" | grep -o 'data-check="[^"]*"' || true)
echo "browser: $dom (expected $expected images)"
if [ "$dom" != "data-check=\"images $expected decoded $expected\"" ]; then
  echo "FAIL: the browser did not decode every image (log: $work/browser.log)" >&2
  tail -5 "$work/browser.log" >&2
  exit 1
fi
echo "ok: $expected images decoded"
