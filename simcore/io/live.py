"""Live stream of frames over the Foxglove WebSocket protocol (``tofradar serve PROJECT``).

Every frame is published on the topics of :mod:`simcore.io.ros2_messages` (``/tf`` and
``/<sensor>/...`` for every sensor of every rig, each sensor's messages logged at its own
capture time, none in a frame it does not capture in) as ROS 2 (CDR) messages with
``ros2msg`` schemas, through the Foxglove SDK's WebSocket server: Foxglove (or any client
of the ``foxglove.websocket.v1`` protocol) shows them as a ROS 2 recording would be shown.
See ``docs/robotics.md`` for what a client receives.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from foxglove.websocket import ChannelView, Client, ServerListener

from simcore.io.ros2_messages import (
    RigDescription,
    encoder,
    frame_messages,
    message_definition,
)
from simcore.pipeline import Simulator
from simcore.scene.model import Project


@dataclass
class ServeReport:
    """What a :func:`serve` call did.

    Attributes
    ----------
    port : int
        The port the server listened on.
    frames_published : int
        Frames sent (each on every topic the frame has).
    """

    port: int
    frames_published: int = 0


class _FirstSubscriber(ServerListener):
    """Server listener that sets an event when a client subscribes to any channel."""

    def __init__(self) -> None:
        self.event = threading.Event()

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        self.event.set()


def serve(project: Project, *, base_dir: Path | None = None, host: str = "127.0.0.1",
          port: int = 8765, n_frames: int | None = None, loop: bool = False,
          realtime: bool = True, wait_for_client: bool = True, linger_s: float = 1.0,
          seed: int | None = None, on_ready: Callable[[int], None] | None = None,
          stop: threading.Event | None = None) -> ServeReport:
    """Simulate frames and publish each on a Foxglove WebSocket server.

    Parameters
    ----------
    project : Project
        The project to simulate.
    base_dir : Path, optional
        Folder that relative mesh paths are resolved against.
    host : str
        Interface to listen on (default: this machine only).
    port : int
        TCP port (0: any free port; ``on_ready`` receives the one chosen).
    n_frames : int, optional
        Frames to publish (default: the project's timeline).
    loop : bool
        Start again at frame 0 after the last frame, until ``stop`` is set.
    realtime : bool
        Publish no faster than the timeline's frame rate.
    wait_for_client : bool
        Start simulating only once a client has subscribed to a topic.
    linger_s : float
        Seconds to keep the server up after the last frame (s).
    seed : int, optional
        Random seed (default: the project's).
    on_ready : callable, optional
        Called with the port once the server listens.
    stop : threading.Event, optional
        Set it to stop between frames.

    Returns
    -------
    ServeReport
    """
    import foxglove

    stop = stop or threading.Event()
    listener = _FirstSubscriber()
    server = foxglove.start_server(name="tofradar", host=host, port=port,
                                   server_listener=listener)
    report = ServeReport(port=server.port)
    channels = {  # every topic of every sensor of every rig
        topic: foxglove.Channel(topic, message_encoding="cdr", schema=foxglove.Schema(
            name=datatype, encoding="ros2msg", data=message_definition(datatype).encode()))
        for topic, datatype in RigDescription.of(project, {}).topics().items()}
    try:
        if on_ready is not None:
            on_ready(report.port)
        while wait_for_client and not listener.event.wait(0.1):
            if stop.is_set():
                return report
        with Simulator(project, base_dir=base_dir, seed=seed) as sim:
            rig = RigDescription.of(project, sim.static_items())
            total = sim.n_frames if n_frames is None else n_frames
            period = 1.0 / project.timeline.frame_rate_hz
            index, started = 0, time.monotonic()
            while not stop.is_set() and (loop or index < total):
                frame = sim.frame(index % total)
                for message in frame_messages(rig, frame.hdf5_items(), frame.table_rows(),
                                              index=frame.index):
                    channels[message.topic].log(encoder(message.datatype)(message.msg),
                                                log_time=message.stamp_ns)
                report.frames_published += 1
                index += 1
                if realtime:
                    time.sleep(max(0.0, started + index * period - time.monotonic()))
        stop.wait(linger_s)
    finally:
        for channel in channels.values():
            channel.close()
        server.stop()
    return report
