"""One Simulation from several threads: steps serialised, reads whole, the single-thread hash."""
import os
import signal
import subprocess
import sys
import textwrap
import threading

import numpy as np

import chainmail

SHEET = {"weave.rows": 16, "weave.cols": 16, "duration": 0.2}
STEPS = 24


def serial_hash(curtain, threads=1):
    sim = chainmail.Simulation(chainmail.load_scene(curtain, SHEET), "plausible", threads=threads)
    sim.step(n=STEPS)
    return sim.hash


def test_four_threads_stepping_and_reading_one_simulation(curtain):
    sim = chainmail.Simulation(chainmail.load_scene(curtain, SHEET), "plausible", threads=2)
    failures = []

    def work(seed):
        try:
            for k in range(STEPS // 4):
                assert sim.step()
                # every kind of read, between and during the other threads' steps
                positions, orientations = sim.positions, sim.orientations
                assert np.isfinite(positions).all() and positions.shape == (256, 3)
                np.testing.assert_allclose(np.linalg.norm(orientations, axis=1), 1.0, rtol=1e-9)
                assert np.isfinite(sim.velocities).all()
                assert sim.metrics()["max_stretch"] > 0.0
                snap = sim.snapshot()
                assert snap["positions"].shape == (256, 3) and np.isfinite(snap["t"])
                assert len(sim.hash) == 16 and sim.steps >= 1
        except Exception as error:  # noqa: BLE001 (reported below, with the thread)
            failures.append((seed, repr(error)))

    team = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in team:
        t.start()
    for t in team:
        t.join()
    assert failures == []
    assert sim.steps == STEPS
    assert sim.hash == serial_hash(curtain)


def test_eight_threads_each_with_their_own_simulation(curtain):
    expected = serial_hash(curtain)
    hashes = [None] * 8

    def work(k):
        hashes[k] = serial_hash(curtain, threads=1 + k % 2)

    team = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in team:
        t.start()
    for t in team:
        t.join()
    assert hashes == [expected] * 8


def test_a_snapshot_is_a_state_between_two_steps(curtain):
    sim = chainmail.Simulation(chainmail.load_scene(curtain, SHEET), "plausible")
    worker = threading.Thread(target=sim.step, kwargs={"n": 40})
    worker.start()
    seen = []
    while worker.is_alive():
        snap = sim.snapshot()
        # t is a whole number of steps: the copy was taken between two of them
        seen.append(round(snap["t"] / sim.dt, 6))
        assert np.isfinite(snap["positions"]).all()
    worker.join()
    assert all(s == int(s) for s in seen)
    assert sim.snapshot()["t"] == sim.t


def test_ctrl_c_in_one_thread_while_others_read_and_step(curtain):
    # the main thread steps (signals go to it) while two threads read and one steps
    script = textwrap.dedent(f"""
        import threading, time, numpy as np, chainmail
        sim = chainmail.Simulation(chainmail.load_scene({curtain!r}, {SHEET!r}), "plausible")
        stop = threading.Event()
        def read():
            while not stop.is_set():
                assert np.isfinite(sim.positions).all() and np.isfinite(sim.snapshot()["t"])
                sim.metrics()
        def step():
            while not stop.is_set():
                sim.step(n=2)
        team = [threading.Thread(target=f) for f in (read, read, step)]
        for t in team:
            t.start()
        print("stepping", flush=True)
        try:
            sim.step(n=10**9)
        except KeyboardInterrupt:
            stop.set()
            for t in team:
                t.join()
            print("interrupted", sim.steps > 0, abs(sim.t - sim.steps * sim.dt) < 1e-9, flush=True)
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                             env=os.environ)
    assert child.stdout.readline().strip() == "stepping"
    threading.Event().wait(1.0)
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=120)
    assert child.returncode == 0, out
    assert out.split() == ["interrupted", "True", "True"]
