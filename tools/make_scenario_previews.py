"""Preview images of sample scenes of the bundled scenario families (docs/scenarios.md).

Run from the repository root:
``PYTHONPATH=. .venv/bin/python tools/make_scenario_previews.py``. For each family in
``resources/scenarios/``, four scenes of seed 0 are generated; each column shows the scene
from above (objects at their pose, the rig and its heading) and the ToF camera's depth
image of frame 0, computed by the simulator.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402

from simcore.pipeline import Simulator  # noqa: E402
from simcore.resources import RESOURCES_DIR  # noqa: E402
from simcore.scenarios import generate  # noqa: E402
from simcore.scene import load_project  # noqa: E402

OUT = Path("docs/images/scenarios")
SCENES = 4


def plan(ax, project) -> None:
    """The scene seen from above: boxes as rotated rectangles, round things as circles."""
    for obj in project.objects:
        g = obj.geometry
        x, y = obj.pose.position_m[0], obj.pose.position_m[1]
        yaw = np.deg2rad(obj.pose.rotation_deg[2])
        colour = "tab:red" if g.kind in ("corner_reflector", "person") else "0.45"
        if g.kind == "box" and g.size_m[2] <= 0.15 and g.size_m[0] * g.size_m[1] > 4.0:
            continue                       # floor and ceiling: they would hide the rest
        if g.kind == "box":
            sx, sy = g.size_m[0] / 2, g.size_m[1] / 2
            c, s = np.cos(yaw), np.sin(yaw)
            corners = [(x + c * dx - s * dy, y + s * dx + c * dy)
                       for dx, dy in ((-sx, -sy), (sx, -sy), (sx, sy), (-sx, sy))]
            ax.add_patch(Polygon(corners, closed=True, fc=colour, ec="k", lw=0.4, alpha=0.6))
        else:
            radius = {"person": 0.22, "corner_reflector": 0.08}.get(g.kind)
            if radius is None:
                radius = float(getattr(g, "radius_m", 0.1))
            ax.add_patch(Circle((x, y), radius, fc=colour, ec="k", lw=0.4, alpha=0.8))
        if g.kind == "person" and obj.motion.keyframes:     # its walk, dashed
            ax.plot([x + k.position_m[0] for k in obj.motion.keyframes],
                    [y + k.position_m[1] for k in obj.motion.keyframes], "--",
                    color="tab:red", lw=0.8)
    rx, ry = project.rig.pose.position_m[0], project.rig.pose.position_m[1]
    heading = np.deg2rad(project.rig.pose.rotation_deg[2])
    ax.arrow(rx, ry, 0.6 * np.cos(heading), 0.6 * np.sin(heading), width=0.05,
             color="tab:blue")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def main() -> int:
    """Write ``docs/images/scenarios/<family>.png`` for every bundled family."""
    OUT.mkdir(parents=True, exist_ok=True)
    for spec in sorted((RESOURCES_DIR / "scenarios").glob("*.json")):
        with tempfile.TemporaryDirectory() as tmp:
            files = generate(spec, tmp, count=SCENES, seed=0)
            fig, axes = plt.subplots(2, SCENES, figsize=(3.4 * SCENES, 6.4),
                                     constrained_layout=True)
            for col, path in enumerate(files):
                project = load_project(path)
                plan(axes[0, col], project)
                axes[0, col].set_title(project.name, fontsize=9)
                sim = Simulator(project, base_dir=path.parent)
                depth = sim.frame(0).hdf5_items()["/tof/depth"][0]
                sim.close()
                im = axes[1, col].imshow(np.where(depth > 0, depth, np.nan), cmap="viridis")
                axes[1, col].set_axis_off()
                fig.colorbar(im, ax=axes[1, col], shrink=0.8, label="ToF depth (m)")
            fig.suptitle(f"{spec.stem}: {SCENES} scenes of seed 0 (top: from above, "
                         "rig in blue; bottom: ToF depth of frame 0)", fontsize=10)
            target = OUT / f"{spec.stem}.png"
            fig.savefig(target, dpi=80)
            plt.close(fig)
            print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
