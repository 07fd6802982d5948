"""Asset import: time to import a 10⁵-triangle glTF, and the office frame rate with it.

    PYTHONPATH=$PWD .venv/bin/python benchmarks/bench_assets.py [--triangles 100000]
        [--nodes 50] [--frames 8] [--rounds 2]

Writes a GLB of ``--nodes`` mesh nodes (UV spheres, ``--triangles`` in all) in a temporary
folder, times ``read_asset`` + ``build_project`` (the whole ``tofradar import``), imports it
into the office example (the spheres in the room, in view of the sensors), and runs
``simcore.bench.run_benchmark`` on the office and on office + asset in alternation (A/B in
the same run, several rounds: the machine may be loaded) to report the frame-rate ratio.
"""

from __future__ import annotations

import argparse
import json
import struct
import tempfile
import time
from pathlib import Path

import numpy as np

from simcore.bench import run_benchmark
from simcore.resources import example_path
from simcore.scene import load_project
from simcore.scene.asset_import import build_project
from simcore.scene.assets import read_asset
from simcore.scene.project_io import save_project


def uv_sphere(n_tri: int, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """A UV sphere of about ``n_tri`` triangles (float32 points, uint32 triangles)."""
    k = max(4, int(np.ceil(np.sqrt(n_tri / 2))))
    th, ph = np.meshgrid(np.linspace(0, np.pi, k + 1), np.linspace(0, 2 * np.pi, k + 1))
    pts = radius * np.stack([np.sin(th) * np.cos(ph), np.cos(th), np.sin(th) * np.sin(ph)],
                            -1).reshape(-1, 3)
    i = (np.arange(k)[:, None] * (k + 1) + np.arange(k)[None, :]).ravel()
    tris = np.concatenate([np.stack([i, i + 1, i + k + 1], 1),
                           np.stack([i + 1, i + k + 2, i + k + 1], 1)])
    return pts.astype(np.float32), tris.astype(np.uint32)


def write_asset(path: Path, n_triangles: int, n_nodes: int) -> None:
    """A GLB of ``n_nodes`` spheres on a grid in the office's free floor area (glTF axes)."""
    doc: dict = {"asset": {"version": "2.0"}, "nodes": [], "meshes": [], "accessors": [],
                 "bufferViews": [], "materials": [{"name": "Painted plastic"}]}
    blob = bytearray()
    pts, tris = uv_sphere(n_triangles // n_nodes, 0.12)
    rng = np.random.default_rng(0)

    def accessor(a: np.ndarray, kind: str, comp: int) -> int:
        blob.extend(b"\0" * (-len(blob) % 4))
        doc["bufferViews"].append({"buffer": 0, "byteOffset": len(blob),
                                   "byteLength": a.nbytes})
        blob.extend(a.tobytes())
        doc["accessors"].append({"bufferView": len(doc["bufferViews"]) - 1,
                                 "componentType": comp, "count": len(a), "type": kind})
        return len(doc["accessors"]) - 1

    for _ in range(n_nodes):      # one mesh per node (no instancing): all data parsed
        bumpy = pts * (1 + 0.05 * rng.random((len(pts), 1))).astype(np.float32)
        doc["meshes"].append({"primitives": [{
            "attributes": {"POSITION": accessor(bumpy.astype(np.float32), "VEC3", 5126)},
            "indices": accessor(tris.ravel(), "SCALAR", 5125), "material": 0}]})
    side = int(np.ceil(np.sqrt(n_nodes)))
    for j in range(n_nodes):
        # project x 1.5…2.3 m ahead, y ±1 m, on the floor: glTF (x, y=up, z=−y_project)
        x, y = 1.5 + 0.8 * (j // side) / side, -1.0 + 2.0 * (j % side) / side
        doc["nodes"].append({"name": f"ball{j}", "mesh": j, "translation": [x, 0.15, -y]})
    doc["scenes"] = [{"nodes": list(range(n_nodes))}]
    doc["scene"] = 0
    doc["buffers"] = [{"byteLength": len(blob)}]
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    blob.extend(b"\0" * (-len(blob) % 4))
    path.write_bytes(struct.pack("<III", 0x46546C67, 2, 28 + len(js) + len(blob))
                     + struct.pack("<II", len(js), 0x4E4F534A) + js
                     + struct.pack("<II", len(blob), 0x004E4942) + bytes(blob))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--triangles", type=int, default=100_000)
    parser.add_argument("--nodes", type=int, default=50)
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--rounds", type=int, default=2)
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="bench_assets_"))
    asset = folder / "balls.glb"
    write_asset(asset, args.triangles, args.nodes)
    office = example_path("office")
    t0 = time.perf_counter()
    scene = read_asset(asset)
    t1 = time.perf_counter()
    result = build_project(scene, folder / "office_assets.json", base=load_project(office))
    save_project(result.project, folder / "office_assets.json")
    t2 = time.perf_counter()
    print(f"asset: {len(scene.objects)} nodes, {scene.n_triangles} triangles, "
          f"{asset.stat().st_size / 2**20:.1f} MiB")
    print(f"import: read {t1 - t0:.2f} s + project and meshes {t2 - t1:.2f} s = "
          f"{t2 - t0:.2f} s")
    fps: dict[str, list[float]] = {"office": [], "office+asset": []}
    cpu: dict[str, list[float]] = {"office": [], "office+asset": []}
    for _ in range(args.rounds):
        for name, path in (("office", office), ("office+asset", folder / "office_assets.json")):
            res = run_benchmark(path, frames=args.frames, antenna_edits=0)
            fps[name].append(res["fps"])
            cpu[name].append(res["cpu_ms_median"])
            stages = ", ".join(f"{k} {v:.0f}" for k, v in res["stages_ms"].items())
            print(f"  {name:<13} {res['fps']:.2f} frames/s (median frame "
                  f"{res['frame_ms_median']:.0f} ms, CPU {res['cpu_ms_median']:.0f} ms; "
                  f"stages ms: {stages})", flush=True)
    a, b = np.median(fps["office"]), np.median(fps["office+asset"])
    rounds = ", ".join(f"{y / x:.2f}" for x, y in zip(fps["office"], fps["office+asset"],
                                                      strict=True))
    print(f"frame rate ratio office+asset / office: {b / a:.2f} (median of {args.rounds} "
          f"rounds each; per round {rounds})")
    # Process CPU time per frame (all threads): less sensitive to other jobs than the
    # wall-clock rate; on a machine as loaded as its cores the rate follows it.
    ca, cb = np.median(cpu["office"]), np.median(cpu["office+asset"])
    print(f"CPU time per frame office / office+asset: {ca:.0f} / {cb:.0f} ms = {ca / cb:.2f}")


if __name__ == "__main__":
    main()
