#!/bin/sh
# ctests ros:msg-genpy and ros:msg-cdr-typescript: our message definitions and codecs
# (orthosonar_msg_dump) against independent implementations.
#   msg_interop.sh genpy <orthosonar_msg_dump> <work dir>
#       genpy (Debian's python3-genpy, by full path: another python3 may come first on
#       PATH) builds each type from our ROS 1 text; see msg_interop.py.
#   msg_interop.sh cdr <orthosonar_msg_dump> <replay/interop source dir> <npm dir> <work dir>
#       Foxglove's @foxglove/rosmsg and rosmsg2-serialization, npm-installed into the build
#       tree by replay/interop/npm_setup.sh (exit 77 = skip only when npm cannot install);
#       see replay/interop/cdr_check.mjs.
set -u
mode=$1
dump=$2
case "$mode" in
  genpy)
    mkdir -p "$3" || exit 1
    exec /usr/bin/python3 "$(dirname "$0")/msg_interop.py" "$dump" "$3"
    ;;
  cdr)
    src=$3
    npm_dir=$4
    work=$5
    . "$src/npm_setup.sh"
    mkdir -p "$work" || exit 1
    exec node "$npm_dir/cdr_check.mjs" "$dump" "$work"
    ;;
  *)
    echo "usage: msg_interop.sh genpy|cdr ..." >&2
    exit 2
    ;;
esac
