#!/usr/bin/env bash
# The nodes' bags (core::BagWriter, rosbag format 2.0 written directly) are read by rosbag's own readers as rosbag's
# writer's are: a short fast run without checkpoints (one run.bag, written by mbd_node itself):
#  - Python rosbag: every topic with its type, each message deserialised, the index's time queries exact (the messages
#    of a time window are those whose stamps fall in it), `rosbag info` and `rosbag check` content;
#  - C++ rosbag (merge_bags reads it with rosbag::View): the same messages, byte for byte, in the joined copy;
#  - a bag cut short as a killed node leaves it (no index): `rosbag reindex` recovers every whole chunk's messages.
source "$(dirname "$0")/ros_env.bash"
/usr/bin/python3 - "$src/launch_free_configs/gyp1200_400rpm.yaml" "$out/case.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["run"].update(duration_s=1.5, settle_s=0.5, checkpoint_every_s=0)
yaml.safe_dump(c, open(sys.argv[2], "w"))
PY
CRUSHER_NO_BUILD=1 CRUSHER_RUN_PLOTS=0 bash "$src/scripts/crusher" run "$out/case.yaml" --out "$out/run" >"$out/run.log" 2>&1 ||
  { tail -n 30 "$out/run.log"; echo "FAIL: crusher run failed"; exit 1; }
bag=$out/run/run.bag
[[ -f $bag && ! -e $out/run/run.seg0000000000.bag ]] || { ls "$out/run"; echo "FAIL: no single run.bag"; exit 1; }
rosbag info "$bag" | head -n 12
rosbag check "$bag" >"$out/check.log" 2>&1 || { cat "$out/check.log"; echo "FAIL: rosbag check"; exit 1; }
grep -q "Bag file does not need any migrations" "$out/check.log" || { cat "$out/check.log"; echo "FAIL: rosbag check"; exit 1; }
rosrun inertia_crusher merge_bags --concat "$out/joined.bag" "$bag" >"$out/merge.log" 2>&1 || { cat "$out/merge.log"; echo "FAIL: merge_bags"; exit 1; }
# A kill: the file up to the middle of its last chunks, no index (index_pos still 0 while a node writes).
/usr/bin/python3 - "$bag" "$out/cut.bag" <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
(index_pos,) = struct.unpack_from("<Q", b, b.index(b"index_pos=") + 10)
cut = b[: index_pos - 3000]  # the last chunk's tail (and the index) lost
cut[b.index(b"index_pos=") + 10 : b.index(b"index_pos=") + 18] = struct.pack("<Q", 0)
open(sys.argv[2], "wb").write(cut)
PY
(cd "$out" && rosbag reindex cut.bag >"$out/reindex.log" 2>&1) || { cat "$out/reindex.log"; echo "FAIL: rosbag reindex"; exit 1; }
/usr/bin/python3 - "$bag" "$out/joined.bag" "$out/cut.bag" <<'PY'
import sys
import genpy, rosbag
bag, joined, cut = sys.argv[1:]
want = {"/crusher/test_point": "inertia_crusher/TestPoint", "/crusher/drive": "inertia_crusher/DriveState",
        "/crusher/product": "inertia_crusher/ProductStream", "/crusher/liners": "visualization_msgs/MarkerArray",
        "/crusher/chamber": "visualization_msgs/MarkerArray", "/tf": "tf2_msgs/TFMessage"}
with rosbag.Bag(bag) as b:
    info = b.get_type_and_topic_info().topics
    for t, ty in want.items():
        assert t in info and info[t].msg_type == ty, (t, info.get(t))
    assert info["/crusher/test_point"].message_count == 750, info["/crusher/test_point"]  # 500 Hz x 1.5 s
    msgs = [(t, m, s) for t, m, s in b.read_messages()]  # deserialised with the stored definitions
    raw = [(t, m[1], s) for t, m, s in b.read_messages(raw=True)]
    assert len(msgs) == sum(i.message_count for i in info.values())
    assert all(a.to_sec() <= c.to_sec() for (_, _, a), (_, _, c) in zip(msgs, msgs[1:])), "not in time order"
    tp = [m for t, m, s in msgs if t == "/crusher/test_point"]
    assert all(abs(m.header.stamp.to_sec() - (k + 1) / 500.0) < 1e-6 for k, m in enumerate(tp)), "test point stamps"
    lo, hi = genpy.Time(0, 600000000), genpy.Time(0, 900000000)  # the index's time query
    window = [s for _, _, s in b.read_messages(start_time=lo, end_time=hi)]
    assert len(window) == sum(1 for _, _, s in msgs if lo <= s <= hi) > 0, len(window)
by_topic = lambda ms: {t: [(m, s) for u, m, s in ms if u == t] for t in info}  # (ties across topics: either order)
with rosbag.Bag(joined) as j:
    assert by_topic([(t, m[1], s) for t, m, s in j.read_messages(raw=True)]) == by_topic(raw), \
        "merge_bags (C++ rosbag) read other messages"
with rosbag.Bag(cut) as c:
    back = [(t, m[1], s) for t, m, s in c.read_messages(raw=True)]
    assert 0 < len(back) < len(raw) and all(x in raw for x in back[:50]), (len(back), len(raw))
print("bag_writer: %d messages on %d topics read back (Python and C++ rosbag); %d recovered from the cut bag"
      % (len(raw), len(info), len(back)))
PY
