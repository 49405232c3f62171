#!/bin/sh
# ctest ros:ros2-typescript-writer (issue 18): a ROS 2 recording written without our code
# (@mcap/core's McapWriter, lz4 chunks, CDR by @foxglove/rosmsg2-serialization, the
# authors' types in ROS 2 form on the authors' topics; replay/interop/ros2_writer.mjs)
# imports with the default mapping and replays to the original mission's maps and
# trajectories. Exits 77 (skip) only when npm cannot install the packages.
#   ros2_typescript.sh <orthosonar> <this dir> <interop dir> <npm dir> <work dir>
set -u
cli=$1
src=$2
interop=$3
npm_dir=$4
work=$5
scene=marina1
seconds=30
here=$src
src=$interop
. "$interop/npm_setup.sh"
src=$here
mkdir -p "$work" || exit 1
cd "$work" || exit 1
rm -rf ./*
fail() { echo "ros2-typescript-writer FAILED: $*"; exit 1; }
. "$src/common.sh"
run orig.mcap out_orig
node "$npm_dir/ros2_writer.mjs" orig.mcap ts.mcap >ts.json || fail "ros2_writer.mjs"
"$cli" import --list ts.mcap >list.txt || fail "import --list ts.mcap: $(cat list.txt)"
"$cli" import ts.mcap -q -o ts_fixture.mcap >/dev/null 2>import.err || fail "import ts.mcap: $(cat import.err)"
run ts_fixture.mcap out_ts
same_maps out_ts "ROS 2 recording by @mcap/core + rosmsg2-serialization"
echo "ros2-typescript-writer: passed ($(cat ts.json))"
