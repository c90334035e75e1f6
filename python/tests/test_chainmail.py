"""The Python module against the command line: same scenes, same errors, same final hashes."""
import json
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import chainmail

SMALL = {"weave.rows": 6, "weave.cols": 6, "duration": 0.2}
SMALL_SETS = [f"{k}={v}" for k, v in SMALL.items()]


def cli_run(binary, scene, backend, out):
    sets = sum((["--set", s] for s in SMALL_SETS), [])
    subprocess.run([binary, "run", scene, "--backends", backend, "--reference", "none",
                    "--cache", "none", "--quiet", "--out", str(out)] + sets, check=True)
    with open(out / "summary.json") as f:
        return json.load(f)


def test_backends_lists_knobs_with_ranges():
    entries = {b["name"]: b for b in chainmail.backends()}
    knobs = {k["name"]: k for k in entries["plausible"]["knobs"]}
    assert entries["plausible"]["built"]
    assert knobs["dt"]["min"] < knobs["dt"]["default"] <= knobs["dt"]["max"]


def test_scene_error_is_the_command_lines_message(curtain, binary):
    with pytest.raises(chainmail.SceneError) as error:
        chainmail.load_scene(curtain, {"weave.rows": -3})
    assert "'weave.rows'" in str(error.value)
    cli = subprocess.run([binary, "check", curtain, "--set", "weave.rows=-3"],
                         capture_output=True, text=True)
    assert cli.returncode == 2
    assert cli.stderr.strip() == "chainmail: " + str(error.value)


def test_a_choice_knob_is_given_listed_and_read_back_by_name(curtain):
    entries = {b["name"]: b for b in chainmail.backends()}
    law = {k["name"]: k for k in entries["torus_xpbd"]["knobs"]}["friction_law"]
    assert (law["type"], law["default"], law["choices"]) == ("choice", "cone", ["cone", "pyramid"])
    scene = chainmail.load_scene(curtain, SMALL)
    sim = chainmail.Simulation(scene, "torus_xpbd", knobs={"friction_law": "pyramid"})
    assert sim.knobs["friction_law"] == "pyramid"
    assert chainmail.Simulation(scene, "torus_xpbd").knobs["friction_law"] == "cone"
    with pytest.raises(chainmail.SceneError, match='friction_law.*"cone", "pyramid"'):
        chainmail.Simulation(scene, "torus_xpbd", knobs={"friction_law": "sphere"})


def test_a_bad_knob_names_its_key(curtain):
    scene = chainmail.load_scene(curtain, SMALL)
    with pytest.raises(chainmail.SceneError, match="backends.plausible.dt"):
        chainmail.Simulation(scene, "plausible", knobs={"dt": -1.0})
    with pytest.raises(chainmail.SceneError, match="backends.plausible.no_such_knob"):
        chainmail.Simulation(scene, "plausible", knobs={"no_such_knob": 1})
    with pytest.raises(chainmail.UsageError, match="nonesuch"):
        chainmail.Simulation(scene, "nonesuch")


def test_arrays_have_the_documented_shapes_and_share_the_frame(curtain):
    sim = chainmail.Simulation(chainmail.load_scene(curtain, SMALL), "plausible")
    positions, orientations = sim.positions, sim.orientations
    assert positions.shape == (36, 3) and positions.dtype == np.float64
    assert orientations.shape == (36, 4) and orientations.dtype == np.float64
    assert sim.velocities.shape == (36, 3)
    np.testing.assert_allclose(np.linalg.norm(orientations, axis=1), 1.0, rtol=1e-12)
    # views, not copies: the arrays taken before a step show the state after it
    assert not positions.flags.owndata and not positions.flags.writeable
    assert np.shares_memory(positions, sim.positions)
    before = positions.copy()
    assert sim.step(n=10)
    assert sim.steps == 10 and sim.t == pytest.approx(10 * sim.dt)
    assert not np.array_equal(positions, before)
    assert np.array_equal(positions, sim.positions)
    with pytest.raises(ValueError):
        positions[0, 0] = 1.0


@pytest.mark.parametrize("backend", ["plausible", "ode"])
def test_stepping_gives_the_command_lines_final_hash(curtain, binary, tmp_path, backend):
    if backend not in {b["name"] for b in chainmail.backends() if b["built"]}:
        pytest.skip(f"{backend} is not built")
    summary = cli_run(binary, curtain, backend, tmp_path / "cli")["backends"][backend]
    sim = chainmail.Simulation(chainmail.load_scene(curtain, SMALL), backend)
    sim.step(n=summary["steps"])
    assert sim.hash == summary["hash"]
    # the same metrics as summary.json's "final" (drape_rms needs a reference run)
    final = {k: v for k, v in summary["final"].items() if k != "drape_rms"}
    assert sim.metrics() == pytest.approx(final, rel=1e-12, nan_ok=True)


def test_run_returns_the_summary_of_the_command_line(curtain, binary, tmp_path):
    cli = cli_run(binary, curtain, "plausible", tmp_path / "cli")
    scene = chainmail.load_scene(curtain, SMALL)
    summary = chainmail.run(scene, backends=["plausible"], reference="none", cache="none")
    assert summary["backends"]["plausible"]["hash"] == cli["backends"]["plausible"]["hash"]
    assert summary["scene"] == cli["scene"]
    kept = chainmail.run(scene, backends=["plausible"], reference="none", cache="none",
                         out=str(tmp_path / "kept"))
    assert (tmp_path / "kept" / "summary.json").is_file()
    assert kept["backends"]["plausible"]["hash"] == cli["backends"]["plausible"]["hash"]


def test_threads_change_nothing_but_the_recorded_count(curtain):
    # 40 x 40 rings: large enough for the plausible step's loops to split
    scene = chainmail.load_scene(curtain, {"weave.rows": 40, "weave.cols": 40, "duration": 0.08})
    hashes = []
    for threads in (1, 2):
        sim = chainmail.Simulation(scene, "plausible", threads=threads)
        sim.step(n=20)
        hashes.append(sim.hash)
    assert hashes[0] == hashes[1]
    summary = chainmail.run(scene, backends=["plausible"], reference="none", cache="none",
                            threads=2)
    assert summary["build"]["threads"] == 2
    assert summary["backends"]["plausible"]["hash"] == hashes[1]
    with pytest.raises(ValueError, match="threads"):
        chainmail.Simulation(scene, "plausible", threads=-1)


def test_sweep_returns_one_row_per_point(curtain, tmp_path):
    scene = chainmail.load_scene(curtain, {"weave.rows": 4, "weave.cols": 4, "duration": 0.04,
                                           "reference": "plausible"})
    result = chainmail.sweep(scene, ["backends.{backend}.dt=0.004,0.002"], backends=["plausible"],
                             out=str(tmp_path / "sweep"), cache="none")
    assert [p["backends.{backend}.dt"] for p in result["points"]] == [0.004, 0.002]
    assert all(p["stable"] is True and p["error_m"] >= 0.0 for p in result["points"])
    assert all(p["verdict"] == "stable" for p in result["points"])
    assert os.path.isfile(os.path.join(result["folder"], "sweep.csv"))


def test_the_gil_is_released_while_stepping(curtain):
    sim = chainmail.Simulation(chainmail.load_scene(curtain, {"weave.rows": 16, "weave.cols": 16}),
                               "plausible")
    worker = threading.Thread(target=sim.step, kwargs={"n": 150})
    counted = 0
    worker.start()
    while worker.is_alive():
        counted += 1
    worker.join()
    assert sim.steps == 150
    assert counted > 1000  # this thread ran Python while the other stepped


def test_ctrl_c_interrupts_a_long_step_loop(curtain):
    script = textwrap.dedent(f"""
        import sys, chainmail
        sim = chainmail.Simulation(chainmail.load_scene({curtain!r}), "plausible")
        print("stepping", flush=True)
        try:
            sim.step(n=10**9)
        except KeyboardInterrupt:
            print("interrupted", sim.steps, abs(sim.t - sim.steps * sim.dt) < 1e-9, flush=True)
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                             env=os.environ)
    assert child.stdout.readline().strip() == "stepping"
    time.sleep(1.0)
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=60)
    assert child.returncode == 0
    word, steps, consistent = out.split()
    assert word == "interrupted" and 0 < int(steps) < 10**9 and consistent == "True"


def test_ctrl_c_stops_a_run_as_on_the_command_line(curtain, tmp_path):
    script = textwrap.dedent(f"""
        import os, chainmail
        scene = chainmail.load_scene({curtain!r}, {{"duration": 100.0}})
        print("running", flush=True)
        try:
            chainmail.run(scene, backends=["plausible"], reference="none", cache="none",
                          out={str(tmp_path / "run")!r})
        except KeyboardInterrupt:
            print("interrupted", os.path.isfile({str(tmp_path / "run" / "summary.json")!r}))
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                             env=os.environ)
    assert child.stdout.readline().strip() == "running"
    time.sleep(1.5)
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=60)
    assert child.returncode == 0
    assert out.split() == ["interrupted", "True"]  # what finished is written, then the exception
    with open(tmp_path / "run" / "summary.json") as f:
        assert json.load(f)["backends"]["plausible"]["verdict"] == "interrupted"


def test_render_returns_an_rgb_image(curtain):
    if not hasattr(chainmail, "render"):
        pytest.skip("built without the renderer")
    scene = chainmail.load_scene(curtain, SMALL)
    sims = [chainmail.Simulation(scene, "plausible"), chainmail.Simulation(scene, "massspring")]
    try:
        image = chainmail.render(sims, width=160, height=90, samples=0)
    except chainmail.SceneError as error:
        pytest.skip(f"no GL here: {error}")
    assert image.shape == (90, 320, 3) and image.dtype == np.uint8
    assert image.std() > 0  # something was drawn


def test_the_drape_example_plots_a_comparison(tmp_path):
    pytest.importorskip("matplotlib")
    from conftest import SOURCE
    out = tmp_path / "drape.png"
    result = subprocess.run([sys.executable, os.path.join(SOURCE, "examples", "drape_comparison.py"),
                             "--backends", "plausible,massspring", "--out", str(out)],
                            capture_output=True, text=True, env=os.environ, timeout=300)
    assert result.returncode == 0, result.stderr
    assert "massspring vs plausible: RMS" in result.stdout
    assert out.stat().st_size > 10000
