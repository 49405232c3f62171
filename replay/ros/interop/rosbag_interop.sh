#!/bin/sh
# ctest ros:rosbag-python-interop: Debian's python3-rosbag against our rosbag reader and
# writer (rosbag_interop.py says what is checked). Python by full path: another python3
# may come first on PATH.
#   rosbag_interop.sh <orthosonar_rosbag_dump> <work dir>
set -u
mkdir -p "$2" || exit 1
exec /usr/bin/python3 "$(dirname "$0")/rosbag_interop.py" "$1" "$2"
