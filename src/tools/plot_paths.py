"""Path plots of a run (imported by plot_run.py): a point of the mantle's bottom edge in world x-y, as it moves and
with the mantle's own spin taken out (the tilt alone; the paper's Figure 19), and the tracked particles of a coupled run
(trajectories.csv: height against time and the path seen from above, Figure 20)."""
import csv
import math
import os

import matplotlib.pyplot as plt


def rotate(q, v):
    """v rotated by the unit quaternion q = (x, y, z, w)."""
    x, y, z, w = q
    c1 = (y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0])
    c2 = (y * c1[2] - z * c1[1], z * c1[0] - x * c1[2], x * c1[1] - y * c1[0])
    return [v[i] + 2 * (w * c1[i] + c2[i]) for i in range(3)]


def swing(q):
    """The tilt part of the rotation q (swing-twist about z): the shortest rotation taking z to q's z axis."""
    a = rotate(q, (0.0, 0.0, 1.0))
    x, y, w = -a[1], a[0], 1.0 + a[2]  # (z x a, 1 + z . a), normalised
    n = math.sqrt(x * x + y * y + w * w)
    return (x / n, y / n, 0.0, w / n)


MANTLE_PATH_S = 3.0  # the last seconds of the mantle's path that mantle_path plots


def mantle_path(liners, out, label, seconds=MANTLE_PATH_S):
    """liners: [(t, (position, quaternion), points)] of the /crusher/liners mantle marker (its liner frame in world;
    the first entry's points, in that frame). Writes mantle_path.png; False if there is nothing to plot."""
    if len(liners) < 3:
        return False
    pts = liners[0][2]
    zmin = min(p[2] for p in pts)
    q = max((p for p in pts if p[2] < zmin + 1e-6), key=lambda p: p[0])  # bottom edge, azimuth 0
    real, still = [], []
    for _, (pos, quat), _ in [x for x in liners if x[0] >= liners[-1][0] - seconds]:
        for dst, r in ((real, quat), (still, swing(quat))):
            w = rotate(r, q)
            dst.append(((w[0] + pos[0]) * 1e3, (w[1] + pos[1]) * 1e3))
    fig, ax = plt.subplots(figsize=(6, 6))
    ax.plot([p[0] for p in real], [p[1] for p in real], lw=0.7, label="as it moves (with the mantle's spin)")
    ax.plot([p[0] for p in still], [p[1] for p in still], lw=0.7, label="spin taken out")
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"mantle bottom-edge point, last {seconds:g} s (Figure 19){label}", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "mantle_path.png"), dpi=110)
    plt.close(fig)
    return True


def particle_paths(path, out, label):
    """trajectories.csv (particle_id,t_s,x_m,y_m,z_m) -> particle_paths.png; False when absent or empty."""
    if not os.path.exists(path):
        return False
    tracks = {}
    with open(path) as f:
        for row in csv.DictReader(f):
            tracks.setdefault(row["particle_id"], []).append(
                (float(row["t_s"]), float(row["x_m"]) * 1e3, float(row["y_m"]) * 1e3, float(row["z_m"]) * 1e3))
    if not tracks:
        return False
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    for pid, tr in sorted(tracks.items()):
        ax[0].plot([p[0] for p in tr], [p[3] for p in tr], lw=0.8, label=f"particle {pid}")
        ax[1].plot([p[1] for p in tr], [p[2] for p in tr], lw=0.8)
    ax[0].set_xlabel("time (s)")
    ax[0].set_ylabel("height z (mm)")
    ax[0].legend(fontsize=7)
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("x (mm)")
    ax[1].set_ylabel("y (mm)")
    fig.suptitle("tracked particle paths: falls, slides and lifts at each squeeze (Figure 20)" + label, fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "particle_paths.png"), dpi=110)
    plt.close(fig)
    return True
