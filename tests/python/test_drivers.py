"""The drivers' two ways to a session give the same numbers: scripts/trubal_session.py (the
module, or the binary on a pipe) and scripts/run_table.py's reading of prepared states (the
module's arrays, or `PRint` through the binary)."""

import os
import sys

import numpy as np

from conftest import IMPACT, ROOT, run_binary, trubal_binary

sys.path.insert(0, os.path.join(ROOT, "scripts"))
import run_table  # noqa: E402
import trubal_session  # noqa: E402


def test_run_table_reads_states_the_same_through_the_module(tmp_path, monkeypatch):
    exe = trubal_binary()
    run_binary(IMPACT + "cycle 800\nsave st.sav\n", tmp_path)
    monkeypatch.setenv("TRUBAL_BIN", exe)  # names a build: the binary's JSON
    assert run_table.module_state(str(tmp_path), "st.sav") is None
    pipe = (run_table.state_summary(exe, str(tmp_path), "st.sav"),
            run_table.wall_height(exe, str(tmp_path), "st.sav"),
            run_table.balls_of(exe, str(tmp_path), "st.sav"))
    monkeypatch.delenv("TRUBAL_BIN")
    assert run_table.module_state(str(tmp_path), "st.sav") is not None
    module = (run_table.state_summary(exe, str(tmp_path), "st.sav"),
              run_table.wall_height(exe, str(tmp_path), "st.sav"),
              run_table.balls_of(exe, str(tmp_path), "st.sav"))
    assert module[0] == pipe[0] and "bridges" in module[0]
    assert module[1] == pipe[1]
    assert [(b["pos"], b["radius"], b["agglomerate"]) for b in module[2]] == \
        [(b["pos"], b["radius"], b["agglomerate"]) for b in pipe[2]]


def test_driver_session_module_and_pipe_agree(tmp_path, monkeypatch):
    out = {}
    for way in ("module", "pipe"):
        d = tmp_path / way
        d.mkdir()
        monkeypatch.chdir(tmp_path)
        if way == "pipe":
            monkeypatch.setenv("TRUBAL_PIPE", "1")
        with open(d / "log", "w") as log:
            s = trubal_session.Session({"v": 0.2}, log, str(d), binary=trubal_binary())
            assert s.module == (way == "module")
            s.send(IMPACT.replace("velocity 0 0 -0.2 0", "velocity 0 0 -$v 0"))
            s.cycle(300)
            e = s.print("energy")
            b = s.balls()
            s.send("save end.sav")
            w = s.print("walls")
            s.close()
        out[way] = (e, np.asarray(b["pos"]).tolist(), np.asarray(b["radius"]).tolist(), w)
    assert out["module"] == out["pipe"]
    assert (tmp_path / "module" / "end.sav").read_bytes() == (tmp_path / "pipe" / "end.sav").read_bytes()


def test_run_table_only_keeps_the_other_finished_rows(tmp_path, monkeypatch):
    """`--only` runs the selected rows; the table's CSV still holds every run finished in the
    work directory (it used to be overwritten with the selected rows alone)."""
    runs = [{"v": v, "eta": 0} for v in (1, 2, 3)]
    monkeypatch.setitem(run_table.TABLES, "fake", {
        "script": "fake.tru", "prepare": [], "runs": runs, "group": "eta", "x": "v", "y": "damage_ratio",
        "fit": False})
    done = {"v1_eta0", "v2_eta0"}  # v3 never ran
    monkeypatch.setattr(run_table, "DATA", str(tmp_path))
    monkeypatch.setattr(run_table, "finished",
                        lambda work, script, r: ([{"print": "info"}], 1.0) if run_table.run_name(r) in done else None)
    monkeypatch.setattr(run_table, "measures", lambda objs, r: {"damage_ratio": 0.1 * r["v"]})
    monkeypatch.setattr(run_table, "draw_table", lambda *a: None)
    monkeypatch.setattr(run_table.provenance, "record", lambda *a, **k: None)
    monkeypatch.setattr(sys, "argv", ["run_table.py", "fake", "--plot-only", "--only", "v=2",
                                      "--work", str(tmp_path / "work")])
    run_table.main()
    with open(tmp_path / "fake.csv") as f:
        vs = [line.split(",")[0] for line in f.read().splitlines()[1:]]
    assert vs == ["1", "2"]


def test_run_table_refuses_a_work_directory_whose_run_has_other_values(tmp_path):
    """Run names leave out n: a table whose run of that name is in the work directory with
    another n must not take that run's results as its own (the trap of issue 53)."""
    import json

    import pytest

    sweep = tmp_path / "sweep_fake"
    sweep.mkdir()
    (sweep / "sweep.json").write_text(json.dumps({"runs": [
        {"name": "v2_theta30", "values": [["state", "/x/a.sav"], ["v", "2"], ["theta", "30"], ["n", "12000"]]}]}))
    same = {"state": "b.sav", "v": "2", "theta": "30", "n": "12000"}
    run_table.same_values(str(tmp_path), "fake.tru", same)  # the same values (state aside)
    run_table.same_values(str(tmp_path), "fake.tru", {"v": "3", "theta": "30", "n": "30000"})  # not there
    with pytest.raises(SystemExit, match="n = 12000, this table's has n = 30000"):
        run_table.finished(str(tmp_path), "fake.tru", dict(same, n="30000"))


def test_run_table_variants_are_their_command_file_with_one_line_added():
    """The command-file variants of run_table (SET TANgential MD, SET GOLdman ON) are written
    from the command file: the same lines with the setting after its anchor, and a header."""
    for name, (base, after, setting) in run_table.VARIANTS.items():
        with open(os.path.join(ROOT, "scripts", base)) as f:
            want = f.read().split("\n")
        k = want.index(after) + 1
        want[k:k] = [setting]
        with open(run_table.script_path(name)) as f:
            got = f.read().split("\n")
        assert got[0].startswith(f"; {name}: scripts/{base}") and got[1:] == want


def test_a_ci_sample_and_a_driver_seed_discard_the_same_numbers(monkeypatch):
    """Sample k of ci_tables.py and a driver's `--seed k` both start k x 10^7 numbers on: the
    CI samples hand the drivers k, not seed(k) (which the drivers would stretch again, to
    10^14 numbers)."""
    import ci_tables
    import lun_shear
    sent = {}

    def fake(exe, tru, sets, work):
        sent.update(sets)
        raise RuntimeError("stop")

    monkeypatch.setattr(lun_shear, "run_json", fake)
    try:
        ci_tables.lun("trubal", "/nonexistent", 2)
    except RuntimeError:
        pass
    assert sent["seed"] == ci_tables.seed(2) == 20_000_000
