"""``tofradar serve``: a Foxglove WebSocket client receives the simulator's frames."""

from __future__ import annotations

import json
import os
import queue
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from simcore.io.ros2_messages import cloud_array, decoder, detection_points
from simcore.pipeline import Simulator
from simcore.resources import example_path
from simcore.scene import load_project

websockets_sync = pytest.importorskip("websockets.sync.client")

ROOT = Path(__file__).resolve().parents[1]
DEADLINE_S = 120.0


def _first_line(proc: subprocess.Popen[str], timeout_s: float) -> str:
    lines: queue.Queue[str] = queue.Queue()
    threading.Thread(target=lambda: lines.put(proc.stdout.readline()), daemon=True).start()
    return lines.get(timeout=timeout_s)


def test_a_foxglove_client_receives_the_simulators_detections() -> None:
    project_path = example_path("point_targets")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "simcore.cli", "serve", str(project_path), "--port", "0",
         "--frames", "4", "--fast"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        env=env, cwd=ROOT)
    received: dict[int, np.ndarray] = {}
    try:
        line = _first_line(proc, 60.0)
        assert line.startswith("serving on ws://127.0.0.1:"), line
        url = line.split()[2]
        deadline = time.monotonic() + DEADLINE_S
        with websockets_sync.connect(url, subprotocols=["foxglove.sdk.v1", "foxglove.websocket.v1"],
                                     open_timeout=30) as ws:
            channels = {}
            while "/radar/detections" not in channels:
                msg = json.loads(ws.recv(timeout=30))
                if msg["op"] == "advertise":
                    channels.update({c["topic"]: c for c in msg["channels"]})
            chan = channels["/radar/detections"]
            assert chan["encoding"] == "cdr" and chan["schemaEncoding"] == "ros2msg"
            assert chan["schemaName"] == "sensor_msgs/msg/PointCloud2"
            ws.send(json.dumps({"op": "subscribe",
                                "subscriptions": [{"id": 7, "channelId": chan["id"]}]}))
            decode = decoder("sensor_msgs/msg/PointCloud2")
            while len(received) < 4 and time.monotonic() < deadline:
                try:
                    data = ws.recv(timeout=max(0.1, deadline - time.monotonic()))
                except TimeoutError:
                    break
                except Exception:  # the server stopped after its last frame
                    break
                if isinstance(data, str) or data[0] != 0x01:
                    continue
                sub_id, log_ns = struct.unpack_from("<IQ", data, 1)
                assert sub_id == 7
                cloud = decode(data[13:])
                stamp = cloud.header.stamp.sec * 10**9 + cloud.header.stamp.nanosec
                assert stamp == log_ns and cloud.header.frame_id == "radar"
                received[stamp] = cloud_array(cloud)
    finally:
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    assert len(received) >= 3, proc.stderr.read() if proc.stderr else ""

    project = load_project(project_path)
    rate = project.timeline.frame_rate_hz
    with Simulator(project) as sim:
        for stamp, points in sorted(received.items()):
            index = round(stamp * 1e-9 * rate)
            frame = sim.frame(index)
            expected = detection_points(frame.table_rows()["/radar/detections"])
            assert set(points.dtype.names) == {"x", "y", "z", "velocity", "snr",
                                               "power_fraction", "label"}
            for name in expected.dtype.names:
                np.testing.assert_array_equal(points[name], expected[name])
            assert sorted(points["label"]) == [1, 2, 3]
