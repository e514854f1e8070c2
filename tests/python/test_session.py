"""`import trubal`: commands, errors, arrays against the binary's own output, energy booking of
the array setters, the bitwise equality with the binary for several thread counts, Ctrl-C."""

import json
import os
import signal
import threading
import time

import numpy as np
import pytest

import trubal
from conftest import FREE, IMPACT, run_binary


def session(deck=IMPACT, threads=1, **kw):
    s = trubal.Session(threads=threads, **kw)
    s.run(deck)
    return s


def test_error_carries_message_line_and_column_and_changes_nothing():
    s = session()
    n = len(s.particles()["id"])
    with pytest.raises(trubal.CommandError) as e:
        s.run("cycle 5\nrad 30e-6 1 frobnicate\ncycle 5")
    err = e.value
    assert err.line == 2
    assert err.column == 13  # `frobnicate` starts at the 13th character
    assert "frobnicate" in str(err) and err.message in str(err)
    # The first line ran, the third did not, the second changed nothing.
    assert s.cycles == 1 + 5
    assert len(s.particles()["id"]) == n


def test_variables_replace_dollar_names():
    s = trubal.Session(threads=1)
    s.run("start $L $L $L 10 10 2", L=0.01)
    s.set_vars(r=1e-3)
    s.run("rad $r 1\ndensity 1000 1\ncreate 0.005 0.005 0.005 0 0 0 0 0 0 1 1")
    assert s.particles()["radius"].tolist() == [1e-3]
    assert s.particles()["position"].tolist() == [[0.005, 0.005, 0.005]]
    with pytest.raises(trubal.CommandError, match=r"\$nope"):
        s.run("rad $nope 1")


def test_particle_arrays_are_print_balls_bit_for_bit():
    s = session(json=True)
    s.cycle(200)
    balls = json.loads(s.run("print balls"))["balls"]
    p = s.particles()
    assert p["position"].shape == (len(balls), 3)
    assert p["id"].tolist() == [b["id"] for b in balls]
    # json's floats are the shortest round-trip texts: equal means the same bits.
    assert p["position"].tolist() == [b["pos"] for b in balls]
    assert p["velocity"].tolist() == [b["vel"] for b in balls]
    assert p["spin"].tolist() == [b["spin"] for b in balls]
    assert p["force"].tolist() == [b["force"] for b in balls]
    assert p["radius"].tolist() == [b["radius"] for b in balls]
    assert p["material"].tolist() == [b["material"] for b in balls]


def contact_sums(s):
    """Each particle's sum of its contacts' forces (on b: +f, on a: -f)."""
    c, p = s.contacts(), s.particles()
    total = np.zeros_like(p["force"])
    np.add.at(total, c["index"][:, 1], c["force"])
    np.add.at(total, c["index"][:, 0], -c["force"])
    return c, p, total


def test_contact_forces_add_up_to_each_particles_force():
    # No gravity, wall or mass damping: a particle's out-of-balance force of the last step is
    # the sum of its contacts' forces, an independent account of the same step. The lattice
    # overlaps (radius raised by 0.5 um); every particle held (Fix, at rest): the step's
    # positions are the positions now, and the sums agree to round-off.
    s = session(FREE)
    s.run("fix 1 1 1 1 1 1 all\nzero 0")
    s.cycle(1)
    c, p, total = contact_sums(s)
    assert c["evaluated"] and len(c["ids"]) == 156  # the BCC lattice's neighbour pairs
    scale = np.abs(p["force"]).max()
    assert scale > 0.1  # newtons: a 0.5 um Hertz overlap of 30 um glass spheres
    assert np.abs(total - p["force"]).max() <= 1e-12 * scale
    assert (p["id"][c["index"]] == c["ids"]).all()
    t = c["touching"]
    assert t.all() and (c["overlap"] > 0).all() and (c["normal_force"] > 0).all()


def test_contact_force_direction_is_the_branch_now():
    # Moving particles: `force` takes the direction of the branch between the positions now,
    # the step computed it between the positions before its update (as PRint Stress and
    # FIEld take it): the sums agree to the rotation of the branches in one step, here
    # within 1 % of the largest force (0.2 % measured).
    s = session(FREE)
    s.cycle(5)
    c, p, total = contact_sums(s)
    scale = np.abs(p["force"]).max()
    assert np.abs(total - p["force"]).max() < 1e-2 * scale


def test_energy_and_stress_are_print_energy_and_stress():
    s = session(json=True)
    s.cycle(500)
    e = json.loads(s.run("print energy"))
    a = s.energy()
    assert a["kinetic"] == e["kinetic"] and a["strain"] == e["strain"]
    assert a["input"] == e["input"] and a["residual"] == e["residual"]
    assert a["dissipated"] == e["dissipated"]["total"]
    assert a["adhesion"] == e["dissipated"]["adhesion"]
    st = json.loads(s.run("print stress"))
    b = s.stress()
    assert b["total"].tolist() == st["stress"]
    assert b["mean"] == st["mean"]


def test_history_and_field():
    s = session()
    s.run("set history 50")
    s.cycle(500)
    h = s.history()
    assert list(h) == list(trubal.HISTORY_COLUMNS)
    assert 9 <= len(h["cycle"]) <= 11
    assert np.all(np.diff(h["cycle"]) == 50) and np.all(np.diff(h["time"]) > 0)
    f = s.field((5, 5, 5), 2.5e-4)
    assert f["density"].shape == (5, 5, 5)
    assert f["stress_contact"].shape == (5, 5, 5, 3, 3)
    # The kernel is normalised on the grid (output/fields.rs): Σ ρ ΔV is the particles' mass.
    dv = np.prod([f[k][1] - f[k][0] for k in "xyz"])
    mass = s.particles()["mass"].sum()
    assert abs(f["density"].sum() * dv - mass) < 1e-9 * mass
    with pytest.raises(trubal.CommandError):
        s.field((5, 5, 5), 1e-9)  # narrower than the node spacing


def test_set_velocities_is_booked_and_atomic():
    s = session(FREE)
    s.cycle(50)
    e0 = s.energy()
    p = s.particles()
    v = np.zeros_like(p["velocity"])
    v[:, 0] = 0.1
    s.set_velocities(v)
    e1 = s.energy()
    assert s.particles()["velocity"].tolist() == v.tolist()
    # The kinetic energy added is booked as the commands' input: the residual does not move.
    assert abs(e1["kinetic_translation"] - 0.5 * p["mass"].sum() * 0.1**2) < 1e-12 * e1["kinetic"]
    added = e1["kinetic"] - e0["kinetic"]
    assert abs((e1["input_commands"] - e0["input_commands"]) - added) <= 1e-12 * abs(added)
    assert abs(e1["residual"] - e0["residual"]) <= 1e-12 * abs(added)
    # Refused arrays change nothing.
    bad = v.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        s.set_velocities(bad)
    with pytest.raises(ValueError, match="rows"):
        s.set_velocities(v[:-1])
    with pytest.raises(ValueError, match="3 columns"):
        s.set_velocities(v[:, :2])
    assert s.particles()["velocity"].tolist() == v.tolist()
    assert s.energy() == e1


def test_set_positions_remakes_contacts_and_refuses_outside():
    s = session(FREE)
    s.cycle(10)
    x = s.particles()["position"]
    y = x + np.array([1e-5, 0, 0])
    s.set_positions(y)
    assert s.particles()["position"].tolist() == y.tolist()
    assert not s.contacts()["evaluated"]  # re-made by the next Cycle, as after MOve
    s.cycle(1)
    assert s.contacts()["evaluated"]
    z = s.particles()["position"]
    out = z.copy()
    out[0, 2] = 2e-3  # beyond the 1 mm work-space
    with pytest.raises(ValueError, match="outside the work-space"):
        s.set_positions(out)
    assert s.particles()["position"].tolist() == z.tolist()


def test_callback_every_k_reads_and_commands():
    s = session()
    seen = []

    def look(sess):
        seen.append((sess.cycles, sess.energy()["kinetic"]))
        if len(seen) == 2:
            sess.run("friction 0.5 1")
        return len(seen) < 4

    ran = s.cycle(1000, every=100, callback=look)
    assert ran == 400
    assert [c for c, _ in seen] == [101, 201, 301, 401]
    assert s.cycles == 401


@pytest.mark.parametrize("threads", [1, 2])
def test_bitwise_equal_to_the_binary(tmp_path, monkeypatch, threads):
    # The binary, one thread, one Cycle; the module in runs of 70 with a callback reading
    # arrays, on `threads` threads: the same checkpoint, byte for byte.
    deck = IMPACT + "cycle 1500\nsave bin.sav\n"
    run_binary(deck, tmp_path, threads=1)
    s = trubal.Session(threads=threads)
    monkeypatch.chdir(tmp_path)
    s.run(IMPACT)
    s.cycle(1500, every=70, callback=lambda sess: sess.particles())
    s.run("save mod.sav")
    assert (tmp_path / "bin.sav").read_bytes() == (tmp_path / "mod.sav").read_bytes()


def test_ctrl_c_raises_keyboard_interrupt_with_a_shorter_cycles_state():
    # Python's own SIGINT handler, whatever the test runner inherited: a process started in
    # the background by a shell without job control ignores SIGINT, and Python then installs
    # no handler (the signal would be lost and the Cycle of 10^8 steps run to its end).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        ctrl_c_stops_the_cycle()
    finally:
        signal.signal(signal.SIGINT, previous)


def ctrl_c_stops_the_cycle():
    s = session()
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        s.cycle(10**8)
    assert time.monotonic() - t0 < 30
    ran = s.cycles - 1
    assert 0 < ran < 10**8
    # The state a `Cycle ran` leaves, bit for bit.
    ref = session()
    ref.cycle(ran)
    a, b = s.particles(), ref.particles()
    assert a["position"].tolist() == b["position"].tolist()
    assert a["velocity"].tolist() == b["velocity"].tolist()
    assert s.energy() == ref.energy()
    # And the session goes on.
    s.cycle(10)
    assert s.cycles == ran + 11


def test_cycling_releases_the_interpreter():
    s = session()
    ticks = 0
    t = threading.Thread(target=lambda: s.cycle(20000))
    t.start()
    while t.is_alive():
        ticks += 1
        time.sleep(0.001)
    t.join()
    assert s.cycles == 20001
    # Holding the interpreter for the whole Cycle would let this loop run once or twice.
    assert ticks > 10


def test_no_scene_yet():
    s = trubal.Session(threads=1)
    with pytest.raises(trubal.CommandError, match="STArt") as e:
        s.particles()
    assert e.value.line is None
    with pytest.raises(trubal.CommandError, match="STArt"):
        s.cycle(5)
