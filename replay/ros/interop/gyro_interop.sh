#!/bin/sh
# ctest ros:gyro-python-interop (issue 32): the paper's vehicle, its fibre-optic gyro
# included, out to the authors' ROS types and back, against Debian's python3-rosbag/genpy.
#   1. simulate `nav_profile: paper` (the DSP-1760's delta angles at 250 Hz on /gyro) and
#      export it (ROS 1 bag, raw images): python3-rosbag reads the kvh_gyro/gyro messages
#      with a class genpy builds from the authors' gyro.msg (gyro_interop.py check-export);
#      the companion topics.yaml carries the gyro's mounting and the latitude;
#   2. importing the bag back (--map that topics.yaml) restores the fixture's gyro mounting
#      and latitude (`config --fixture`), and the replay's maps and trajectories are the
#      original's, the dead reckoning's heading from the gyro included;
#   3. python3-rosbag writes a bag with kvh_gyro/gyro messages of its own (status false and
#      an empty delta among them, as the authors' gyro_node publishes an unparsed packet);
#      we import it (the default topics: /gyro) and export it again, and python reads the
#      same messages back.
#   gyro_interop.sh <orthosonar> <dir of gyro_interop.py and common.sh> <work dir> [scene] [seconds]
set -u
cli=$1
src=$2
work=$3
scene=${4:-marina1}
seconds=${5:-20}
py=/usr/bin/python3
mkdir -p "$work" || exit 1
cd "$work" || exit 1
rm -rf ./*
fail() { echo "gyro-python-interop FAILED: $*"; exit 1; }

printf 'nav_profile: paper\n' >paper.yaml
sim_args="--sim-config paper.yaml"
. "$src/common.sh"
run orig.mcap out_orig

# 1. Our export, read by python3-rosbag.
"$cli" export orig.mcap --to ros1-bag --image raw -q -o raw.bag >/dev/null || fail "export"
grep -q '^  gyro: "' raw.topics.yaml || fail "raw.topics.yaml has no gyro mount: $(cat raw.topics.yaml)"
grep -q '^latitude_deg: 40.706' raw.topics.yaml || fail "raw.topics.yaml has no latitude_deg: $(cat raw.topics.yaml)"
"$py" "$src/gyro_interop.py" check-export raw.bag "$seconds" || fail "python3-rosbag reads our /gyro"

# 2. Back into a fixture: the same gyro configuration and the same maps.
"$cli" import raw.bag --map raw.topics.yaml -q -o back.mcap >/dev/null || fail "import raw.bag"
"$cli" config --fixture back.mcap >cfg_back.yaml || fail "config --fixture back.mcap"
"$py" - cfg.yaml cfg_back.yaml <<'PY' || fail "the imported fixture's gyro configuration differs"
import json, sys
a, b = (json.load(open(p))["dr"] for p in sys.argv[1:3])
for k in ("T_V_gyro", "latitude_deg", "use_gyro"):
    if a[k] != b[k]: sys.exit("dr.%s: original %r, imported %r" % (k, a[k], b[k]))
print("imported fixture: dr.T_V_gyro %s, dr.latitude_deg %s as the original's" % (b["T_V_gyro"], b["latitude_deg"]))
PY
run back.mcap out_back
same_maps out_back "ros1 bag with kvh_gyro/gyro"

# 3. python3-rosbag writes, we import and export, python reads.
"$py" "$src/gyro_interop.py" write raw.bag py.bag expected.json || fail "python3-rosbag writes kvh_gyro/gyro"
"$cli" import py.bag -o py.mcap >import.txt 2>&1 || fail "import py.bag: $(cat import.txt)"
grep -q "gyro: " import.txt || fail "import py.bag imported no gyro: $(cat import.txt)"
"$cli" export py.mcap --to ros1-bag --image raw -q -o py_back.bag >/dev/null || fail "export py.mcap"
"$py" "$src/gyro_interop.py" compare py_back.bag expected.json || fail "python3-rosbag reads back its gyro"
echo "gyro-python-interop: all passed"
