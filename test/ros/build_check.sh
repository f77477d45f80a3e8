#!/usr/bin/env bash
# `crusher run` and the other commands build only when the build is not current (catkin_make on a current tree cost
# 3-4 s of every run): current when a stamp of the last successful build is newer than every file and folder the
# build compiles, the workspace links this repository and the nodes exist. `crusher build --check` says which.
# A fake build root (no compiler run): the stamp's age stands in for edits.
source "$(dirname "$0")/ros_env.bash"
repo=$(cd "$src" && pwd -P)
root=$out/buildroot
mkdir -p "$root/ws/src" "$root/ws/devel/lib/inertia_crusher"
ln -s "$repo" "$root/ws/src/inertia_crusher"
node=$root/ws/devel/lib/inertia_crusher/mbd_node
printf '#!/bin/sh\n' >"$node"
chmod +x "$node"
fail() { echo "FAIL: $1"; exit 1; }
check() {  # EXPECTED_RC PATTERN: `crusher build --check` exits so and says it
  local rc=0 said
  said=$(CRUSHER_BUILD_ROOT=$root "$src/scripts/crusher" build --check 2>&1) || rc=$?
  echo "rc $rc: $said"
  [[ $rc == "$1" && $said == $2 ]] || fail "expected exit $1 and '$2', got $rc: '$said'"
}
check 1 "not current: no successful build in $root"
touch -d '+1 hour' "$root/build.stamp"
check 0 "current"
touch -d '2000-01-01' "$root/build.stamp"  # every source is newer: an edit
check 1 "not current: * changed since the last build"
touch -d '+1 hour' "$root/build.stamp"
rm "$node"
check 1 "not current: the built nodes are missing"
printf '#!/bin/sh\n' >"$node"
chmod +x "$node"
ln -sfn "$out" "$root/ws/src/inertia_crusher"
check 1 "not current: the workspace links another repository"
echo "the build check: current only with a newer stamp, the nodes and this repository"
