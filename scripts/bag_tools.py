"""Shared by the bag-reading scripts (bed_profile.py, run_windows.py)."""
import sys

import rosbag


def open_bag(path, tool):
    """The bag for reading, or exit naming what is wrong with it."""
    try:
        return rosbag.Bag(path)
    except rosbag.ROSBagUnindexedException:
        sys.exit(f"{tool}: {path} is unindexed: still being written, or its node was killed "
                 "(`rosbag reindex` mends it)")
    except (OSError, rosbag.ROSBagException) as e:
        sys.exit(f"{tool}: {path} cannot be read as a bag ({e})")
