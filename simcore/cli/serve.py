"""``tofradar serve``: publish frames live over the Foxglove WebSocket protocol."""

from __future__ import annotations

import argparse
from pathlib import Path

from simcore.cli.common import (
    _frames_int,
    _int_at_least,
    _Parser,
    _preflight,
    _seed_int,
    stop_on_sigint,
)
from simcore.scene.project_io import load_project


def cmd_serve(args: argparse.Namespace) -> int:
    """Publish frames live over the Foxglove WebSocket protocol."""
    from simcore.io.live import serve

    project_path = Path(args.project)
    project = load_project(project_path)
    _preflight(project, project_path, args, n_frames=args.frames, seed=args.seed)

    def ready(port: int) -> None:
        print(f"serving on ws://{args.host}:{port} (Foxglove WebSocket protocol)", flush=True)

    with stop_on_sigint() as stop:
        report = serve(project, base_dir=project_path.parent, host=args.host, port=args.port,
                       n_frames=args.frames, loop=args.loop, realtime=not args.fast,
                       wait_for_client=not args.no_wait, seed=args.seed, on_ready=ready,
                       stop=stop)
    print(f"published {report.frames_published} frames")
    return 0


def add_parser(sub: argparse._SubParsersAction[_Parser], common: list[_Parser]) -> None:
    """The ``serve`` subcommand."""
    p = sub.add_parser("serve", help="publish frames live over the Foxglove WebSocket protocol",
                       parents=common)
    p.add_argument("project", help="project JSON file")
    p.add_argument("--host", default="127.0.0.1", help="interface (default 127.0.0.1)")
    p.add_argument("--port", type=_int_at_least(0, 65535), default=8765,
                   help="TCP port (default 8765; 0 = any free port)")
    p.add_argument("--frames", type=_frames_int, help="frames to publish (default: timeline)")
    p.add_argument("--loop", action="store_true", help="repeat the timeline until Ctrl+C")
    p.add_argument("--fast", action="store_true",
                   help="publish as fast as frames are computed (default: timeline frame rate)")
    p.add_argument("--no-wait", action="store_true",
                   help="start at once (default: wait until a client subscribes)")
    p.add_argument("--seed", type=_seed_int, help="random seed (default: project's)")
    p.set_defaults(func=cmd_serve)
