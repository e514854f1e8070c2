#!/usr/bin/env python3
"""What made a data file: the program version, the exact command and the date (issue 53 item 1).

Every script that writes a data file under doc/data or doc/img calls `record(path, exe)` right
after writing it; that writes PATH.provenance.json next to it:

    {"file": "lun_shear.csv", "version": "trubal 0.1.0", "git": "c856b99-dirty",
     "binary": "target/release/trubal", "command": "python3 scripts/lun_shear.py",
     "date": "2026-12-06T23:10:00Z"}

`version` is `trubal -V` of the binary that ran, `git` is `git describe --always --dirty` of
the source tree (the build the binary came from when it was built from this tree: the
scripts build it through cargo unless TRUBAL_BIN names another), `command` is the command
line of the script (sys.argv, with the python3 in front) and `TRUBAL_BIN` when it was set.
TRUBAL_BUILD_REV=COMMIT replaces `git` when TRUBAL_BIN is a copy of the build of COMMIT
(the tree may move on while a long run goes).

    python3 scripts/provenance.py FILE...    prints the provenance of the files (or "none")

Python 3 standard library only.
"""
import datetime
import functools
import json
import os
import shlex
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@functools.lru_cache(maxsize=None)
def version(exe):
    """`trubal -V` of the binary exe."""
    try:
        return subprocess.run([exe, "-V"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError) as e:
        return f"unknown ({e})"


@functools.lru_cache(maxsize=None)
def git_describe():
    """`git describe --always` of the source tree, with `-dirty` when the program's sources or
    the scripts have uncommitted changes (regenerate from a commit; the run's own outputs in
    doc/ do not count), or TRUBAL_BUILD_REV when set (the commit a copied binary, TRUBAL_BIN,
    was built from, while the tree moves on)."""
    if os.environ.get("TRUBAL_BUILD_REV"):
        return os.environ["TRUBAL_BUILD_REV"]
    try:
        rev = subprocess.run(["git", "describe", "--always", "--tags"], cwd=ROOT,
                             capture_output=True, text=True, check=True).stdout.strip()
        changed = subprocess.run(
            ["git", "status", "--porcelain", "--", "src", "Cargo.toml", "Cargo.lock", "scripts"],
            cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
        return rev + "-dirty" if changed else rev
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def command():
    """The command line that runs now, as a shell would take it."""
    argv = list(sys.argv)
    if argv and os.path.isabs(argv[0]) and argv[0].startswith(ROOT):
        argv[0] = os.path.relpath(argv[0], ROOT)
    env = f"TRUBAL_BIN={shlex.quote(os.environ['TRUBAL_BIN'])} " if os.environ.get("TRUBAL_BIN") else ""
    return env + "python3 " + " ".join(shlex.quote(a) for a in argv)


def stamp(exe, cmd=None):
    """The provenance fields of a run of the binary exe by the command cmd (default: this
    script's command line)."""
    binary = os.path.relpath(exe, ROOT) if os.path.isabs(exe) and exe.startswith(ROOT) else exe
    return {
        "version": version(exe),
        "git": git_describe(),
        "binary": binary,
        "command": cmd or command(),
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }


def sidecar(path):
    return path + ".provenance.json"


def record(path, exe, cmd=None, **extra):
    """Writes PATH.provenance.json: the provenance of the data file `path`, just written by a
    run of the binary exe; extra fields (e.g. seeds, notes) are added as given."""
    d = {"file": os.path.basename(path)}
    d.update(stamp(exe, cmd))
    d.update(extra)
    with open(sidecar(path), "w") as fh:
        json.dump(d, fh, indent=1)
        fh.write("\n")
    return d


def read(path):
    """The provenance of `path`, or None when it has none."""
    try:
        with open(sidecar(path)) as fh:
            return json.load(fh)
    except OSError:
        return None


if __name__ == "__main__":
    if {"-h", "--help"} & set(sys.argv[1:]):
        sys.exit(print("usage: scripts/provenance.py FILE ...  (prints what made each data file)"))
    for p in sys.argv[1:]:
        d = read(p)
        print(p + ": " + (json.dumps(d) if d else "none"))
