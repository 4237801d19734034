#!/usr/bin/env bash
# Idempotent set-up of a Debian machine for CadRobot (run by `make demo` and
# `make test`): Debian 12 (FreeCAD 0.20), and inside the Debian roots of
# tools/debian_root.sh, trixie (1.0) and sid (1.1). Checks first and only installs
# what is missing, so a second run is a fast no-op.
#
#   1. apt: FreeCAD, Xvfb, Debian's numpy/scipy/pytest/hypothesis/yaml/pip/pygments (and Qt 6's
#      SVG plugin where FreeCAD runs on Qt 6)
#   2. PyPI packages of requirements-freecad.txt for FreeCAD's interpreter, in
#      FreeCAD's AdditionalPythonPackages folder (what the Addon Manager uses):
#        FreeCAD 0.20/0.21: <UserAppData>/AdditionalPythonPackages
#        FreeCAD 1.x:       <UserAppData>/AdditionalPythonPackages/py<XY>
#      FreeCAD appends that folder to sys.path at start-up when it exists.
#   3. <UserAppData>/Mod/CadRobot -> this repository (FreeCAD loads the workbench)
#   4. cadrobot launcher on PATH (/usr/local/bin/cadrobot -> ./cadrobot)
#
# Usage: tools/setup.sh                      set up (from any working directory)
#        tools/setup.sh --print-packages-dir print the AdditionalPythonPackages
#                                            folder (for PYTHONPATH) and exit
set -euo pipefail

REPO="$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")/.." && pwd -P)"
REQUIREMENTS="$REPO/requirements-freecad.txt"
# FreeCAD's Python on Debian is the system interpreter (never a pyenv/venv one).
FC_PY="${CADROBOT_FREECAD_PYTHON:-/usr/bin/python3}"
APT_PACKAGES=(freecad xvfb xauth libgl1-mesa-dri python3-numpy python3-scipy python3-matplotlib
              python3-pytest python3-yaml python3-pip python3-dask python3-distributed
              python3-pygments python3-hypothesis)
# Qt 6 draws SVG icons (our tree and toolbar icons) only with its SVG image plugin, a
# Recommends of Qt 6 that --no-install-recommends leaves out; Qt 5 FreeCAD depends on it.
QT6_SVG_PACKAGE=qt6-svg-plugins
# Held around every apt-get of ours (tools/debian_root.sh takes it too).
APT_LOCK=/var/lib/apt/cadrobot.lock

say() { printf 'setup: %s\n' "$*"; }
die() { printf 'setup: ERROR: %s\n' "$*" >&2; exit 1; }

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"
    elif command -v sudo >/dev/null 2>&1; then sudo "$@"
    else die "need root (or sudo) to run: $*"; fi
}

find_freecadcmd() {
    local c
    for c in freecadcmd FreeCADCmd freecadcmd-daily; do
        if command -v "$c" >/dev/null 2>&1; then command -v "$c"; return 0; fi
    done
    return 1
}

# ---------------------------------------------------------------- 1. apt
install_apt_packages() {
    local missing=() p
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" \
            || missing+=("$p")
    done
    if [ "${#missing[@]}" -eq 0 ]; then
        say "apt packages present"
        return 0
    fi
    local log="${TMPDIR:-/tmp}/cadrobot-setup-apt.log"
    say "apt-get install ${missing[*]} (log: $log)"
    export DEBIAN_FRONTEND=noninteractive
    # One apt at a time: CI builds the Debian roots (tools/debian_root.sh installs
    # debootstrap) beside this set-up, and apt-get update fails at once on a held lock.
    local one_apt=(flock "$APT_LOCK" apt-get -o DPkg::Lock::Timeout=900)
    if ! { as_root "${one_apt[@]}" update -q && \
           as_root "${one_apt[@]}" install -y -q --no-install-recommends "${missing[@]}"; } \
           >"$log" 2>&1 </dev/null; then
        tail -n 25 "$log" >&2
        die "apt-get failed (full log: $log)"
    fi
}

# ------------------------------------------------- FreeCAD's own answers
# Ask FreeCAD itself where its user folders are and what it puts on sys.path.
FC_INFO_CODE='
import FreeCAD, json, os, sys
uad = FreeCAD.getUserAppDataDir()
major = int(FreeCAD.Version()[0])
base = os.path.join(uad, "AdditionalPythonPackages")
# 1.x: the Addon Manager uses a folder per Python version, FreeCADInit puts both
# base/pyXY and base on sys.path; 0.20/0.21 know only base.
target = os.path.join(base, "py%d%d" % sys.version_info[:2]) if major >= 1 else base
norm = lambda p: os.path.normcase(os.path.realpath(p))
print("CADROBOT_FCINFO " + json.dumps({
    "uad": uad, "version": ".".join(FreeCAD.Version()[:3]),
    "python": "%d.%d" % sys.version_info[:2], "target": target,
    "target_on_path": any(p and norm(p) == norm(target) for p in sys.path),
    "sys_path": sys.path}))
'

FC_INFO=""
query_freecad() {
    local fccmd
    fccmd="$(find_freecadcmd)" || die "freecadcmd not found after installing freecad"
    FC_INFO="$(cd / && "$fccmd" -c "$FC_INFO_CODE" </dev/null 2>/dev/null \
               | sed -n 's/^CADROBOT_FCINFO //p')"
    [ -n "$FC_INFO" ] || die "could not query FreeCAD ($fccmd -c ...)"
}

info() {  # info KEY -> value from FC_INFO
    "$FC_PY" -c '
import json, sys
v = json.loads(sys.argv[1])[sys.argv[2]]
print(int(v) if isinstance(v, bool) else v if isinstance(v, str) else json.dumps(v))' "$FC_INFO" "$1"
}

if [ "${1:-}" = "--print-packages-dir" ]; then
    query_freecad
    info target
    exit 0
elif [ $# -gt 0 ]; then
    die "unknown argument: $1 (usage: tools/setup.sh [--print-packages-dir])"
fi

install_apt_packages "${APT_PACKAGES[@]}"
if dpkg-query -W -f='${Status}\n' 'libqt6gui6*' 2>/dev/null | grep -q "install ok installed"; then
    install_apt_packages "$QT6_SVG_PACKAGE"
fi
query_freecad
UAD="$(info uad)"; UAD="${UAD%/}"
TARGET="$(info target)"
say "FreeCAD $(info version) (Python $(info python)), user data: $UAD"

# FreeCAD >= 1.1 keeps using the unversioned user folder of an older FreeCAD, but its GUI
# then asks in a modal dialog whether to migrate it, and under Xvfb (GUI tests, demo
# screenshots) nobody answers. The marker file is what the dialog's "share the configuration
# with the previous version" answer writes (src/Gui/Dialogs/DlgVersionMigrator.cpp).
keep_unversioned_user_folder() {
    local major minor
    IFS=. read -r major minor _ <<<"$(info version)"
    if [ "$major" -gt 1 ] || { [ "$major" -eq 1 ] && [ "$minor" -ge 1 ]; }; then
        case "$(basename "$UAD")" in
            v[0-9]*-[0-9]*) ;;
            *) touch "$UAD/v$major-$minor.do_not_migrate"
               say "FreeCAD $major.$minor shares $UAD with the older FreeCAD (no migration dialog)" ;;
        esac
    fi
}
keep_unversioned_user_folder

fc_py_version="$("$FC_PY" -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
[ "$fc_py_version" = "$(info python)" ] || die "$FC_PY is Python $fc_py_version but FreeCAD runs Python $(info python); set CADROBOT_FREECAD_PYTHON to FreeCAD's interpreter"

# ------------------------------------------------------- 2. PyPI packages
# One helper, run with FreeCAD's interpreter:
#   check  TARGET REQS        exit 0 when every pinned requirement is installed in TARGET
#   verify TARGET REQS PATHJSON  every dependency of what is in TARGET resolves (target
#                             first, as PYTHONPATH gives it), and notes what FreeCAD's own
#                             sys.path order shadows
#   prune  TARGET REQS        remove stale dist-info of requirements about to be replaced
PKG_HELPER='
import json, os, re, shutil, sys
from importlib import metadata
from pip._vendor.packaging.requirements import Requirement
from pip._vendor.packaging.utils import canonicalize_name as canon

mode, target, reqfile = sys.argv[1:4]

def requirements():
    out = []
    for line in open(reqfile, encoding="utf-8"):
        line = line.split("#", 1)[0].strip()
        if line:
            out.append(Requirement(line))
    return out

def dists(paths):
    found = {}
    for d in metadata.distributions(path=paths):
        name = d.metadata["Name"]
        if name:
            found.setdefault(canon(name), d)   # first on the path wins, like import
    return found

def satisfied(req, found):
    d = found.get(canon(req.name))
    return d is not None and req.specifier.contains(d.version, prereleases=True)

reqs = requirements()
in_target = dists([target]) if os.path.isdir(target) else {}
if mode == "check":
    missing = [str(r) for r in reqs if not satisfied(r, in_target)]
    print(" ".join(missing))
    sys.exit(1 if missing else 0)
if mode == "prune":
    for r in reqs:
        if not satisfied(r, in_target) and os.path.isdir(target):
            for entry in os.listdir(target):
                m = re.match(r"(.+?)-[^-]+\.(dist-info|egg-info)$", entry)
                if m and canon(m.group(1)) == canon(r.name):
                    shutil.rmtree(os.path.join(target, entry), ignore_errors=True)
    sys.exit(0)
# verify
fc_path = [p for p in json.loads(sys.argv[4]) if p and os.path.isdir(p)]
norm = lambda p: os.path.normcase(os.path.realpath(p))
everywhere = dists([target] + [p for p in sys.path if p and os.path.isdir(p)])
problems = []
for key, d in sorted(in_target.items()):
    for spec in d.requires or []:
        r = Requirement(spec)
        if r.marker is not None and not r.marker.evaluate({"extra": ""}):
            continue
        if not satisfied(r, everywhere):
            have = everywhere.get(canon(r.name))
            problems.append("%s %s needs %s (%s)" % (d.metadata["Name"], d.version, r,
                            "found %s" % have.version if have else "not installed"))
for p in problems:
    print("setup: ERROR: " + p + ": add it to requirements-freecad.txt (or install the Debian package)", file=sys.stderr)
# What FreeCAD itself will import: its sys.path has the target last.
before = [p for p in fc_path if norm(p) != norm(target)]
fc_first = dists(before)
for key, d in sorted(in_target.items()):
    other = fc_first.get(key)
    if other is not None and other.version != d.version:
        print("setup: note: inside FreeCAD, %s %s from %s shadows %s in AdditionalPythonPackages"
              % (d.metadata["Name"], other.version, str(other.locate_file("")), d.version))
sys.exit(1 if problems else 0)
'

pkg_helper() { "$FC_PY" -c "$PKG_HELPER" "$@"; }

install_python_packages() {
    local changed=0 missing stamp="$TARGET/.cadrobot-verified" want
    # The stamp says "verified against this requirements file and this FreeCAD".
    want="$(cksum <"$REQUIREMENTS") FreeCAD $(info version)"
    if [ ! -d "$TARGET" ]; then
        mkdir -p "$TARGET"
        changed=1
    fi
    [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] || changed=1
    if missing="$(pkg_helper check "$TARGET" "$REQUIREMENTS")"; then
        say "Python packages present in $TARGET"
    else
        rm -f "$stamp"
        say "pip install into $TARGET: $missing"
        pkg_helper prune "$TARGET" "$REQUIREMENTS"
        local log="${TMPDIR:-/tmp}/cadrobot-setup-pip.log"
        # --target: PEP 668 does not apply; --no-deps: see requirements-freecad.txt;
        # --upgrade: replace older copies already in the folder.
        if ! "$FC_PY" -m pip install --no-deps --upgrade --target "$TARGET" \
                --disable-pip-version-check --no-input --root-user-action=ignore \
                --no-warn-script-location -r "$REQUIREMENTS" >"$log" 2>&1 </dev/null; then
            tail -n 25 "$log" >&2
            die "pip install failed (full log: $log)"
        fi
        missing="$(pkg_helper check "$TARGET" "$REQUIREMENTS")" \
            || die "still missing after pip install: $missing"
        changed=1
    fi
    if [ "$changed" -eq 1 ]; then
        [ "$(info target_on_path)" = 1 ] || query_freecad   # FreeCAD saw no folder before
        [ "$(info target_on_path)" = 1 ] \
            || die "FreeCAD does not put $TARGET on sys.path"
        pkg_helper verify "$TARGET" "$REQUIREMENTS" "$(info sys_path)"
        verify_imports
        printf '%s\n' "$want" >"$stamp"
    fi
}

verify_imports() {
    # The packages must import inside FreeCAD (freecadcmd), not only in plain Python.
    local fccmd out
    fccmd="$(find_freecadcmd)"
    out="$(cd / && "$fccmd" -c '
import importlib, os, sys
for name in ("trimesh", "fcl", "rapidchecker", "numba"):
    m = importlib.import_module(name)
    print("CADROBOT_IMPORT %s %s" % (name, os.path.dirname(os.path.dirname(m.__file__))))
' </dev/null 2>&1)" || true
    if [ "$(printf '%s\n' "$out" | grep -c '^CADROBOT_IMPORT ')" -ne 4 ]; then
        printf '%s\n' "$out" >&2
        die "trimesh/fcl/rapidchecker/numba do not import inside FreeCAD"
    fi
    say "imports OK inside freecadcmd: $(printf '%s\n' "$out" | sed -n 's/^CADROBOT_IMPORT \([^ ]*\) .*/\1/p' | tr '\n' ' ')"
}

# ------------------------------------------------- 3. link into Mod folder
link_workbench() {
    local mod="$UAD/Mod" link="$UAD/Mod/CadRobot"
    if [ -L "$link" ] && [ "$(readlink -f "$link")" = "$REPO" ]; then
        say "workbench linked: $link -> $REPO"
        return 0
    fi
    mkdir -p "$mod"
    if [ -L "$link" ]; then
        say "relinking $link (was -> $(readlink "$link"))"
        rm -f "$link"
    elif [ -e "$link" ]; then
        local backup="$link.backup-$(date +%Y%m%d-%H%M%S)"
        say "moving existing $link aside to $backup"
        mv "$link" "$backup"
    fi
    ln -s "$REPO" "$link"
    say "workbench linked: $link -> $REPO"
}

# ------------------------------------------------ 4. launcher on the PATH
link_launcher() {
    local dir=/usr/local/bin
    [ -x "$REPO/cadrobot" ] || chmod +x "$REPO/cadrobot"
    if [ ! -w "$dir" ]; then
        dir="$HOME/.local/bin"
        mkdir -p "$dir"
    fi
    local link="$dir/cadrobot"
    if [ -L "$link" ] && [ "$(readlink -f "$link")" = "$REPO/cadrobot" ]; then
        say "launcher present: $link"
    elif [ -e "$link" ] && [ ! -L "$link" ]; then
        say "WARNING: $link exists and is not our link; leaving it alone"
    else
        ln -sfn "$REPO/cadrobot" "$link"
        say "launcher linked: $link -> $REPO/cadrobot"
    fi
    case ":$PATH:" in
        *":$dir:"*) ;;
        *) say "note: $dir is not on your PATH; add it or run $REPO/cadrobot" ;;
    esac
}

install_python_packages
link_workbench
link_launcher
say "done"
