"""A trubal session for the drivers: the Python module (`import trubal`, doc/python.md: the
binary's own session in-process, arrays without text, an error raised at its line) when it
is installed (`pip install .`), else the binary on a pipe (`trubal - --json`), the way the
drivers talked to it before the module.

Both give the same calls: `send(text)` (commands), `print(item)` (a PRint item's JSON
object), `ask(text, kind)` (the JSON object of kind `kind` a command prints), `balls()` (positions and radii: numpy arrays from the module, lists from the pipe),
`cycle(n)`, and `close()`; `module` says which one runs.
"""

import json
import os
import subprocess

try:
    import trubal
except ImportError:  # the module is not installed: the pipe
    trubal = None


class Session:
    """A session in directory `work`, `$name`s from `sets`, messages to the file `log`."""

    def __init__(self, sets, log, work, binary=None, threads=None):
        threads = int(threads or os.environ.get("TRUBAL_THREADS", "1"))
        self.module = trubal is not None and os.environ.get("TRUBAL_PIPE") is None
        self.log = log
        if self.module:
            # Relative file names (SAve, RESTart, plots) are the process's: work there.
            os.chdir(work)
            self.s = trubal.Session(threads=threads, json=True)
            self.s.set_vars(**sets)
            return
        args = [binary or "trubal", "--json", "-", "--threads", str(threads)]
        for k, v in sets.items():
            args += ["--set", f"{k}={v}"]
        self.p = subprocess.Popen(args, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  stderr=log, text=True, bufsize=1, cwd=work)

    def send(self, text):
        if self.module:
            out = self.s.run(text)
            if out:
                self.log.write(out)
                self.log.flush()
            return
        self.p.stdin.write(text if text.endswith("\n") else text + "\n")
        self.p.stdin.flush()

    def print(self, item):
        """PRint item: its JSON object (other lines are skipped)."""
        return self.ask(f"print {item}", item)

    def ask(self, text, kind):
        """The command `text`: the JSON object it prints with `print: kind` (`FIEld`'s is
        "field"); other lines are skipped."""
        if self.module:
            for line in self.s.run(text).splitlines():
                if line.startswith("{"):
                    o = json.loads(line)
                    if o.get("print") == kind:
                        return o
            raise RuntimeError(f"`{text}` printed no {kind}")
        self.send(text)
        while True:
            line = self.p.stdout.readline()
            if not line:
                raise RuntimeError(f"trubal ended before `{text}` answered (see the log)")
            if line.startswith("{"):
                o = json.loads(line)
                if o.get("print") == kind:
                    return o

    def balls(self):
        """{"pos": (n, 3), "radius": (n,)}: numpy arrays from the module, lists from the pipe."""
        if self.module:
            p = self.s.particles()
            return {"pos": p["position"], "radius": p["radius"]}
        b = self.print("balls")["balls"]
        return {"pos": [x["pos"] for x in b], "radius": [x["radius"] for x in b]}

    def cycle(self, n):
        if self.module:
            self.s.cycle(int(n))
        else:
            self.send(f"cycle {int(n)}")

    def close(self):
        if self.module:
            return
        self.send("stop")
        self.p.stdin.close()
        self.p.wait()
