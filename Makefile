# tofradar: two commands do all set-up on a fresh machine.
#   make run   - install into .venv, then open the GUI on the demo project
#                (or run the headless demo where no display exists)
#   make test  - install (with GUI and test extras and the system packages GUI tests need), run
#                every check, including the built wheel in a fresh venv (check-wheel)
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
DEMO := resources/examples/office.json

# Debian packages: Xvfb for the GUI tests, the xcb libraries Qt's xcb plugin loads, Mesa for VTK.
SYSDEPS := xvfb xauth imagemagick libxcb-icccm4 libxcb-image0 libxcb-keysyms1 libxcb-randr0 \
	libxcb-render-util0 libxcb-shape0 libxcb-xinerama0 libxcb-xkb1 libxkbcommon-x11-0 \
	libxcb-cursor0 libegl1 libgl1 libegl-mesa0 libgl1-mesa-dri libglx-mesa0 libdbus-1-3 \
	libfontconfig1

# pytest-xdist workers: the core suite on every core (CORE_WORKERS=0: one process); the GUI
# suite in one process by default, since each GUI test already keeps two cores busy (its
# simulation process, Mesa's software OpenGL threads, Xvfb): on this 2-core machine 182 GUI
# tests took 8 m 11 s in one process and 10 m 18 s with -n 2 (GUI_WORKERS=auto; each worker
# gets an Xvfb of its own). worksteal: an idle worker takes tests queued on a busy one.
CORE_WORKERS ?= auto
GUI_WORKERS ?= 0
CORE_XDIST := -n $(CORE_WORKERS) --dist worksteal
GUI_XDIST := -n $(GUI_WORKERS) --dist worksteal

.PHONY: run test install sysdeps lint typecheck importlint static-checks pytest-core pytest-gui \
	pytest-suites check-wheel bench report clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[gui,test]'
	touch $(STAMP)

install: $(STAMP)

run: $(STAMP)
	@if [ -n "$$DISPLAY" ] || [ -n "$$WAYLAND_DISPLAY" ]; then \
		$(VENV)/bin/tofradar gui $(DEMO); \
	else \
		echo "No display found: running the headless demo instead (dataset and previews in out/)."; \
		mkdir -p out && $(VENV)/bin/tofradar run $(DEMO) --out out/demo.h5 --frames 10 \
			--seed 1 --overwrite --preview out/preview; \
	fi

sysdeps:
	@missing=""; for p in $(SYSDEPS); do \
		dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
		echo "Installing system packages:$$missing"; \
		if [ "$$(id -u)" = 0 ]; then SUDO=""; else SUDO="sudo"; fi; \
		$$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null; \
	fi

lint: $(STAMP)
	$(VENV)/bin/ruff check simcore app tests benchmarks

typecheck: $(STAMP)
	$(VENV)/bin/mypy

importlint: $(STAMP)
	$(VENV)/bin/lint-imports

static-checks: lint typecheck importlint

# Core tests need no display: DISPLAY is removed so that they prove it.
pytest-core: $(STAMP)
	env -u DISPLAY $(PY) -m pytest -m "not gui" -q $(CORE_XDIST)

# GUI tests drive real windows on a virtual X server (exit status 5 = none collected).
pytest-gui: $(STAMP) sysdeps
	xvfb-run -a -s "-screen 0 1920x1080x24" $(PY) -m pytest -m gui -q $(GUI_XDIST); \
		rc=$$?; if [ $$rc -eq 5 ]; then rc=0; fi; exit $$rc

# The built wheel, installed without the GUI extra into a fresh venv outside the repository,
# runs `tofradar validate` and `tofradar run` on a bundled example from a temporary folder.
check-wheel: $(STAMP)
	tools/check_wheel.sh $(PY)

# The two suites one after the other, their output shown as they run.
pytest-suites: $(STAMP) sysdeps
	@$(MAKE) --no-print-directory -Onone pytest-core
	@$(MAKE) --no-print-directory -Onone pytest-gui

# Every check. The wheel check (mostly waiting on pip: building, then installing the
# dependencies into a fresh venv) and the static checks run beside the test suites; their
# output is shown whole when each ends. Any part that fails fails `make test`, after the
# parts already running have ended.
test: $(STAMP) sysdeps
	@$(MAKE) --no-print-directory -j 3 -Otarget pytest-suites check-wheel static-checks

bench: $(STAMP)
	$(VENV)/bin/tofradar bench

# Regenerate the validation report (figures + docs/validation/README.md).
report: $(STAMP)
	$(VENV)/bin/tofradar report --out docs/validation

clean:
	rm -rf $(VENV) out build dist *.egg-info .pytest_cache .mypy_cache .ruff_cache
