"""The open project: current :class:`Project`, file path, undo stack, selection and time.

Every edit replaces the project by a new, validated copy through a
:class:`ReplaceProjectCommand` on the undo stack, then the document emits one
``projectChanged`` signal. Projects are never mutated in place, so the simulation worker can
keep using the copy it was given while the user goes on editing.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path
from typing import Any

from pydantic import ValidationError
from PyQt6.QtCore import QObject, QStandardPaths, pyqtSignal
from PyQt6.QtGui import QUndoCommand, QUndoStack

from app.document.identity import follow_sensor
from app.document.validation import FIELD_WORDS, describe_validation_error, plain_name
from simcore.resources import EXAMPLES_DIR
from simcore.scene import (
    DualBandMaterial,
    Project,
    fieldpath,
    load_material_library,
    load_project,
    save_project,
)
from simcore.scene.project_io import ProjectError, check_references

#: Selection key of the sensor rig (objects are selected by their integer id).
RIG = "rig"
#: Selection keys of the further rigs (issue #30): ``"rig:<name>"``.
RIG_KEY_PREFIX = "rig:"

#: Folder of the last project opened or saved in this session (Save As starts there).
_LAST_FOLDER: list[Path] = []


def is_bundled_example(path: str | Path) -> bool:
    """True when ``path`` lies in the bundled examples folder (resolved: it is a link)."""
    try:
        return Path(path).resolve().is_relative_to(EXAMPLES_DIR.resolve())
    except OSError:
        return False


def remember_last_folder(recent_files: list[str]) -> None:
    """Start Save As in the folder of the newest recent file that is not an example.

    The main window calls this with its recent-files list, so the last used folder carries
    over from the previous session.
    """
    for f in recent_files:
        if not is_bundled_example(f) and Path(f).parent.is_dir():
            _LAST_FOLDER[:] = [Path(f).parent]
            return


def documents_folder() -> Path:
    """The user's documents folder (home when the platform names none)."""
    found = QStandardPaths.writableLocation(QStandardPaths.StandardLocation.DocumentsLocation)
    return Path(found) if found else Path.home()

_MERGE_IDS: dict[str, int] = {}


def _merge_id(key: str | None) -> int:
    """Small integer for a merge key (``QUndoCommand.id`` must be an int); never re-used."""
    if key is None:
        return -1
    if key not in _MERGE_IDS:
        _MERGE_IDS[key] = 1000 + _next_merge_serial()
    return _MERGE_IDS[key]


_SERIAL = [0]


def _next_merge_serial() -> int:
    _SERIAL[0] += 1
    return _SERIAL[0]


@lru_cache(maxsize=1)
def _library() -> dict[str, DualBandMaterial]:
    return load_material_library()


def library_names() -> set[str]:
    """Names of the bundled library's materials."""
    return set(_library())


def library_material(name: str) -> DualBandMaterial | None:
    """The bundled library's material ``name`` (None: not a library material)."""
    return _library().get(name)


class EditError(ValueError):
    """An edit produced an invalid project; the message names the bad field.

    ``errors`` holds the model's errors (pydantic's dicts: ``loc``, ``type``, ``ctx``,
    ``input``, in SI), so that the field that was edited can say what is wrong in its own
    label and unit (:func:`app.editors.field_editors.commit_value`).
    """

    def __init__(self, message: str, *, errors: list[dict[str, Any]] | None = None):
        super().__init__(message)
        self.errors: list[dict[str, Any]] = list(errors or [])


class ReplaceProjectCommand(QUndoCommand):
    """Undoable replacement of the document's project by an edited copy.

    Consecutive commands with the same merge key (e.g. the steps of one drag) merge into
    one undo step that restores the project from before the first step.
    """

    def __init__(self, document: ProjectDocument, before: Project, after: Project, text: str,
                 merge_key: str | None = None):
        super().__init__(text)
        self._document = document
        self.before = before
        self.after = after
        self._id = _merge_id(merge_key)

    def id(self) -> int:  # noqa: D102 - Qt API
        return self._id

    def mergeWith(self, other: QUndoCommand) -> bool:  # noqa: N802, D102 - Qt API
        if not isinstance(other, ReplaceProjectCommand) or other.id() != self.id():
            return False
        self.after = other.after
        return True

    def redo(self) -> None:  # noqa: D102 - Qt API
        self._document._set_project(self.after)

    def undo(self) -> None:  # noqa: D102 - Qt API
        self._document._set_project(self.before)


class ProjectDocument(QObject):
    """The project being edited, its file and its history.

    Signals
    -------
    projectChanged(Project)
        After every edit, undo, redo, new or open.
    projectReplaced()
        A different project was created or opened (views rebuild everything).
    pathChanged(object)
        The file path changed (``Path`` or ``None``).
    dirtyChanged(bool)
        The project differs (or no longer differs) from the saved file.
    selectionChanged(object)
        Selected object id, :data:`RIG` (the first rig), ``"rig:<name>"`` (a further rig,
        issue #30), or ``None``.
    currentSensorChanged(str, str)
        The sensor of a kind (``"tof"``, ``"radar"``, ``"rgb"``) that the sensor editor,
        antenna editor and array analysis edit changed to the named one: picked by the
        user, renamed, or gone (then the first of its kind).
    """

    projectChanged = pyqtSignal(object)
    projectReplaced = pyqtSignal()
    pathChanged = pyqtSignal(object)
    dirtyChanged = pyqtSignal(bool)
    selectionChanged = pyqtSignal(object)
    currentSensorChanged = pyqtSignal(str, str)

    def __init__(self, project: Project | None = None, path: Path | None = None,
                 parent: QObject | None = None):
        super().__init__(parent)
        self.undo_stack = QUndoStack(self)
        # A bound method, not a lambda: Qt drops the connection when the document goes.
        self.undo_stack.cleanChanged.connect(self._on_clean_changed)
        self._project = project if project is not None else Project()
        self._path = path
        self._template: Path | None = None
        self._selection: int | str | None = None
        #: The sensor of each kind that the editors edit (issue #30).
        self._current: dict[str, str | None] = {}
        self._materials: dict[str, DualBandMaterial] = {}
        self._materials_for: Project | None = None
        #: ``before_push(old, new)`` runs before an edit is pushed and raises
        #: :class:`EditError` to refuse it (cost checks and confirmations of the window).
        self.before_push: Callable[[Project, Project], None] | None = None

    def _on_clean_changed(self, clean: bool) -> None:  # noqa: FBT001 - Qt slot
        self.dirtyChanged.emit(not clean)

    # --- state ------------------------------------------------------------------------
    @property
    def project(self) -> Project:
        """The current project (treat as read-only: edit through :meth:`edit`)."""
        return self._project

    @property
    def path(self) -> Path | None:
        """The project file, or ``None`` for a project never saved (or an opened example)."""
        return self._path

    @property
    def template(self) -> Path | None:
        """The bundled example this project was opened from and not yet saved elsewhere.

        Examples are templates: the document has no file (:attr:`path` is ``None``), so Save
        asks for a location, and :meth:`save` refuses to write into the examples folder.
        """
        return self._template

    @property
    def display_name(self) -> str:
        """File name for titles: ``office.json``, ``office (example)`` or ``untitled``."""
        if self._path is not None:
            return self._path.name
        if self._template is not None:
            return f"{self._template.stem} (example)"
        return "untitled"

    @property
    def base_dir(self) -> Path:
        """Folder that relative mesh paths are resolved against."""
        if self._path is not None:
            return self._path.parent
        if self._template is not None:
            return self._template.parent
        return Path.cwd()

    def suggested_save_path(self) -> Path:
        """Where Save As starts: the last folder used, with the project's file name.

        The last folder opened or saved in this session (never the examples folder), else
        the project's own folder, else the user's documents folder.
        """
        if self._path is not None:
            name = self._path.name
        elif self._template is not None:
            name = self._template.name
        else:
            name = f"{self._project.name or 'untitled'}.json"
        folders = [*_LAST_FOLDER[-1:]]
        if self._path is not None:
            folders.append(self._path.parent)
        folders.append(documents_folder())
        folder = next(f for f in folders if not is_bundled_example(f / name))
        return folder / name

    @property
    def is_dirty(self) -> bool:
        """True when there are unsaved changes."""
        return not self.undo_stack.isClean()

    @property
    def selection(self) -> int | str | None:
        """Selected object id, :data:`RIG` or ``None``."""
        return self._selection

    def material_table(self) -> dict[str, DualBandMaterial]:
        """Library materials overridden by the project's, keyed by name (cached per project).

        Same result as :func:`simcore.scene.project_io.material_table`, without reading the
        library file on every call.
        """
        if self._materials_for is not self._project:
            table = dict(_library())
            table.update({m.name: m for m in self._project.materials})
            self._materials = table
            self._materials_for = self._project
        return self._materials

    def select(self, key: int | str | None) -> None:
        """Select an object by id, a rig (:data:`RIG`, ``"rig:<name>"``) or nothing."""
        if key is not None and not self._selectable(key, self._project):
            key = None
        if key != self._selection:
            self._selection = key
            self.selectionChanged.emit(key)

    @staticmethod
    def _selectable(key: int | str, project: Project) -> bool:
        """Whether ``key`` names an object or a rig of ``project``."""
        if key == RIG:
            return True
        if isinstance(key, str):
            return key.startswith(RIG_KEY_PREFIX) and any(
                r.name == key[len(RIG_KEY_PREFIX):] for r in project.rigs)
        return any(o.id == key for o in project.objects)

    def current_sensor(self, kind: str) -> str | None:
        """Name of the sensor of ``kind`` that the editors edit (None: the project has none).

        The first rig's built-in one (``tof``, ``radar``) until another is picked with
        :meth:`set_current_sensor`; it follows renames, undo and redo.
        """
        names = self._project.sensors_of_kind(kind)
        name = self._current.get(kind)
        return name if name in names else next(iter(names), None)

    def set_current_sensor(self, kind: str, name: str) -> None:
        """Let the editors of ``kind`` sensors edit sensor ``name`` (KeyError if absent)."""
        if name not in self._project.sensors_of_kind(kind):
            raise KeyError(f"no {kind} sensor {name!r}")
        if self.current_sensor(kind) != name:
            self._current[kind] = name
            self.currentSensorChanged.emit(kind, name)
        self._current[kind] = name

    def selected_index(self) -> int | None:
        """Index in ``project.objects`` of the selected object, or ``None``."""
        for i, obj in enumerate(self._project.objects):
            if obj.id == self._selection:
                return i
        return None

    def index_of(self, object_id: int) -> int:
        """Index in ``project.objects`` of the object with ``object_id`` (KeyError)."""
        for i, obj in enumerate(self._project.objects):
            if obj.id == object_id:
                return i
        raise KeyError(object_id)

    # --- editing ----------------------------------------------------------------------
    def validated(self, data: dict[str, Any]) -> Project:
        """Validate an edited project document; raise :class:`EditError` naming the field."""
        try:
            project = Project.model_validate(data)
        except ValidationError as exc:
            raise EditError("; ".join(describe_validation_error(exc)),
                            errors=[dict(e) for e in exc.errors()]) from None
        problems = check_references(project, self.base_dir)
        if problems:
            raise EditError("; ".join(problems))
        return project

    def edit(self, text: str, mutate: Callable[[dict[str, Any]], None], *,
             merge_key: str | None = None) -> Project:
        """Apply ``mutate`` to a copy of the project document and push it as one undo step.

        Parameters
        ----------
        text : str
            Undo-menu text, e.g. "Move sphere".
        mutate : callable
            Changes the plain ``dict`` (``Project.model_dump()``) in place.
        merge_key : str, optional
            Consecutive edits with the same key merge into one undo step (drags, sliders).

        Returns
        -------
        Project
            The new project.

        Raises
        ------
        EditError
            The edit makes the project invalid; the project is left unchanged.
        """
        data = self._project.model_dump()
        mutate(data)
        new = self.validated(data)
        self.push(new, text, merge_key=merge_key)
        return new

    def push(self, new: Project, text: str, *, merge_key: str | None = None) -> None:
        """Push the replacement of the project by ``new`` (already validated)."""
        if new == self._project:
            return
        if self.before_push is not None:
            self.before_push(self._project, new)  # raises EditError to refuse
        self.undo_stack.push(ReplaceProjectCommand(self, self._project, new, text, merge_key))

    def set_value(self, path: str, value: Any, *, text: str | None = None,
                  merge_key: str | None = None) -> Project:
        """Set one field named by its field path, e.g. ``objects[3].pose.position_m``.

        The path syntax is :mod:`simcore.scene.fieldpath`'s, the one sweeps use.
        """
        parts = fieldpath.parse(path)
        name = next((p for p in reversed(parts) if isinstance(p, str)), path)

        def mutate(data: dict[str, Any]) -> None:
            fieldpath.set_in(data, path, copy.deepcopy(value))

        words = FIELD_WORDS.get(name) or plain_name(name)
        return self.edit(text or f"Set {words}", mutate, merge_key=merge_key)

    def end_merge(self) -> None:
        """Close the current merge run (a drag ended): the next edit starts a new step."""
        _MERGE_IDS.clear()

    def _set_project(self, project: Project) -> None:
        before, self._project = self._project, project
        moved = []
        for kind, name in list(self._current.items()):
            now = None if name is None else follow_sensor(before, project, name, kind)
            if now != name:
                self._current[kind] = now
                moved.append((kind, now))
        if self._selection is not None and not self._selectable(self._selection, project):
            self._selection = None
            self.selectionChanged.emit(None)
        for kind, now in moved:
            if now is not None:
                self.currentSensorChanged.emit(kind, now)
        self.projectChanged.emit(project)

    # --- files ------------------------------------------------------------------------
    def replace(self, project: Project, path: Path | None, *,
                template: Path | None = None) -> None:
        """Start over with ``project`` (New, Open): clears history and selection."""
        self.undo_stack.clear()
        self._path = path
        self._template = template
        self._selection = None
        self._current = {}
        self._project = project
        self.undo_stack.setClean()
        self.pathChanged.emit(path)
        self.selectionChanged.emit(None)
        self.projectReplaced.emit()
        self.projectChanged.emit(project)
        self.dirtyChanged.emit(False)

    def new(self, project: Project | None = None) -> None:
        """Replace by a new, unsaved project."""
        self.replace(project if project is not None else Project(), None)

    def open(self, path: str | Path) -> None:
        """Load ``path``; on :class:`ProjectError` the current project stays untouched.

        A bundled example opens as a template: no file (Save asks where), see
        :attr:`template`.
        """
        path = Path(path)
        project = load_project(path)
        if is_bundled_example(path):
            self.replace(project, None, template=path.resolve())
        else:
            self.replace(project, path.resolve())
            _LAST_FOLDER[:] = [path.resolve().parent]

    def save(self, path: str | Path | None = None) -> Path:
        """Save atomically to ``path`` (default: the current file) and mark clean.

        Raises
        ------
        ValueError
            No file name (a new project or an opened example): use ``save(path)``.
        PermissionError
            ``path`` is in the bundled examples folder (examples are read-only templates).
        """
        target = Path(path) if path is not None else self._path
        if target is None:
            raise ValueError("no file name: use save(path)")
        target = target.resolve()
        if is_bundled_example(target):
            raise PermissionError(f"{target} is a bundled example (a read-only template); "
                                  "save the project in another folder")
        save_project(self._project, target)
        _LAST_FOLDER[:] = [target.parent]
        if target != self._path:
            self._path = target
            self._template = None
            self.pathChanged.emit(target)
        self.undo_stack.setClean()
        return target


__all__ = ["RIG", "EditError", "ProjectDocument", "ProjectError", "ReplaceProjectCommand",
           "documents_folder", "is_bundled_example", "remember_last_folder"]
