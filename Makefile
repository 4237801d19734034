# CadRobot -- `make demo` and `make test` each run their own idempotent set-up.
SHELL := /bin/bash

# FreeCAD's interpreter on Debian. Never a pyenv/venv python: FreeCAD's modules
# and the packages in its AdditionalPythonPackages folder are built for this one.
PY           := /usr/bin/python3
FREECAD_RUN  := $(PY) tools/freecad_run.py
PYTEST_IN_FC := $(PY) tools/run_pytest_in_freecad.py
OUT          := out
# The independent checkers (rapidchecker, ...) are part of what the tests prove:
# under make, a missing checker fails its tests instead of skipping them.
export CADROBOT_REQUIRE_CHECKERS := 1

.PHONY: setup demo test test-core test-app test-gui test-install test-1.1 test-1.0 test-all bench clean

setup:
	@bash tools/setup.sh

# The paper's example cells, their programs and simulations, written under out/,
# a screenshot of each cell (out/<document>.png, real GUI under Xvfb), and the seam
# cell built again with the toolbar, a screenshot per step (out/walkthrough/), and a new
# user's first cell on FreeCAD's own Drilling_1 part with the defaults (out/first_cell/), and
# a fillet weld all round an angle cleat on a plate with the defaults (out/fillet_cell/); the
# welded seam and T-joint (issue 22) and the woven path close up (out/tee_joint_weave.png);
# a pipe welded to its flange all round, flat, on a tilt-and-turn positioner (issue 23:
# out/pipe_flange.FCStd, out/external_axes/, the player with the positioner turned in
# out/pipe_flange_player.png).
demo: setup
	@test -f examples/make_demo.py || { echo "make demo: examples/make_demo.py is missing" >&2; exit 1; }
	$(FREECAD_RUN) --clean-stdout --timeout 1800 examples/make_demo.py $(OUT)
	$(FREECAD_RUN) --gui --clean-stdout --timeout 600 examples/screenshots.py $(OUT)
	$(FREECAD_RUN) --gui --clean-stdout --timeout 600 examples/gui_walkthrough.py $(OUT)
	$(FREECAD_RUN) --gui --clean-stdout --timeout 900 examples/first_cell.py $(OUT)
	$(FREECAD_RUN) --gui --clean-stdout --timeout 900 examples/fillet_cell.py $(OUT)
	$(FREECAD_RUN) --gui --clean-stdout --timeout 600 examples/pipe_flange_player.py $(OUT)

# All tiers, even when one fails; fails if any failed.
test: setup
	@failed=""; \
	for tier in test-core test-app test-gui test-install; do \
	    echo "=== $$tier"; \
	    $(MAKE) --no-print-directory $$tier || failed="$$failed $$tier"; \
	done; \
	if [ -n "$$failed" ]; then echo "make test: FAILED:$$failed" >&2; exit 1; fi; \
	echo "make test: core, App, GUI and install tiers passed"

# Every tier runs as one pytest process per CPU sharing the tier's test files, longest
# first (tools/parallel_pytest.py; CADROBOT_TEST_WORKERS=1 for one process). Add
# SAVE_DURATIONS=--save-durations to record each file's seconds in tests/durations.json.

# Plain pytest, no FreeCAD. The PyPI packages (trimesh, rapidchecker) live in
# FreeCAD's AdditionalPythonPackages folder, so put it on PYTHONPATH here.
test-core:
	@pkgs="$$(bash tools/setup.sh --print-packages-dir)" || { echo "make test-core: run 'make setup' first" >&2; exit 1; }; \
	echo "PYTHONPATH=$$pkgs $(PY) tools/parallel_pytest.py --tier core tests/core -q"; \
	PYTHONPATH="$$pkgs" $(PY) tools/parallel_pytest.py --tier core $(SAVE_DURATIONS) tests/core -q

# pytest inside FreeCADCmd: real documents, Part, Sketcher. Each FreeCAD has a user
# folder of its own: the user's preferences, robots and macros are left alone.
test-app:
	$(PYTEST_IN_FC) --timeout 1800 $(SAVE_DURATIONS) tests/app -q

# pytest inside the real FreeCAD GUI on Xvfb (saveImage works), a display per worker.
test-gui:
	$(PYTEST_IN_FC) --gui --allow-empty --timeout 1200 $(SAVE_DURATIONS) tests/gui -q

# The workbench installed as FreeCAD 1.x's Addon Manager installs it (a new user's
# empty home, no set-up of ours), then used headless and from the toolbar.
test-install:
	$(PY) tools/parallel_pytest.py --tier install --timeout 1800 $(SAVE_DURATIONS) tests/install -q

# The same tiers with the FreeCAD of a Debian root (built once with debootstrap and
# cached in /var/cache/cadrobot/roots; tools/debian_root.sh): sid has 1.1 (Qt 6),
# trixie 1.0. `make test` is the host's FreeCAD (Debian 12: 0.20.2).
test-1.1:
	bash tools/debian_root.sh 1.1 make test
test-1.0:
	bash tools/debian_root.sh 1.0 make test
test-all: test test-1.1 test-1.0

# Speed, measured against a peer in the same run (printed, never asserted).
bench: setup
	$(FREECAD_RUN) --clean-stdout bench/bench_ik.py
	$(FREECAD_RUN) --clean-stdout bench/bench_chain.py
	$(FREECAD_RUN) --clean-stdout bench/bench_long_path.py
	@packages="$$(bash tools/setup.sh --print-packages-dir)"; \
	for b in bench_collision bench_check bench_seam bench_arc bench_force bench_numeric_ik bench_chain_ik bench_place bench_external; do \
	    PYTHONPATH="$$packages" $(PY) bench/$$b.py || exit 1; \
	done

clean:
	rm -rf $(OUT) .pytest_cache
	find . -path ./.git -prune -o -type d -name __pycache__ -prune -exec rm -rf {} +
	find . -path ./.git -prune -o -type f \( -name '*.FCBak' -o -name '*.pyc' \) -exec rm -f {} +
