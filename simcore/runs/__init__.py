"""Runs: a project's frames into a dataset, from one scene, a folder of scenes or a sweep.

``runner.py`` computes frames (in process, on a process pool or on Dask) and drives the
dataset writers: :func:`~simcore.runs.runner.run_dataset` for one project,
:func:`~simcore.runs.runner.run_scenes` for a folder of scenes in one dataset.
``sweep.py`` expands ``--vary`` field ranges into project variants.

Runs sit above the pipeline: they may import :mod:`simcore.pipeline`, :mod:`simcore.io`,
:mod:`simcore.preflight`, the sensors and the scene model, never the command line
(:mod:`simcore.cli`), the report or the GUI.
"""
