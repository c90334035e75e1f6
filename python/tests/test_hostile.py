"""A generated hostile corpus for the Python API: every case is refused with an exception naming
the argument (ValueError, of which SceneError and UsageError are kinds, or TypeError for a wrong
type), never a crash, and nothing is written."""
import math
import os

import pytest

import chainmail

SMALL = {"weave.rows": 4, "weave.cols": 4, "duration": 0.02}
NUMBERS = [float("nan"), float("inf"), float("-inf"), -1.0, 0.0, 1e300, -1e300, 1e9, 5e-324]
TYPES = ["x", None, [], {}, (1,), object(), b"1", 1 + 2j]


def case(name, call, error, token):
    return pytest.param(call, error, token, id=name)


def scene_cases():
    bad_paths = {"nul": "a\0b.json", "nul_end": "scene.json\0", "empty": "",
                 "missing": "/nonexistent/scene.json", "folder": "/", "device": "/dev/null",
                 "long": "x" * 5000 + ".json"}
    for key, path in bad_paths.items():
        yield case(f"load_scene.path.{key}", lambda s, p=path: chainmail.load_scene(p),
                   ValueError, "" if key != "nul" and key != "nul_end" else "path")
    overrides = {"weave.rows": [-3, 0, 10**9, 2.5, "x", None, float("nan"), float("inf"), True],
                 "weave.cols": [-1, 0, 10**7, "4", []],
                 "duration": [-1.0, 0.0, float("nan"), float("inf"), 1e300, "1"],
                 "ring.wire_diameter": [-1.0, 0.0, float("nan"), 1.0, "thin"],
                 "gravity": [float("nan"), "down", [0, 0], [0, 0, float("inf")]],
                 "no_such_key": [1], "weave.type": ["8in1", 3, None],
                 "backends.plausible.dt": [0.0, -1.0, 1e9, float("nan"), "fast"],
                 "backends.plausible.iterations": [0, -5, 10**12, 2.5],
                 "backends.nonesuch.dt": [0.001]}
    for key, values in overrides.items():
        for k, value in enumerate(values):
            yield case(f"load_scene.overrides.{key}.{k}",
                       lambda s, key=key, value=value: chainmail.load_scene(s, {key: value}),
                       ValueError, key.split(".")[0])
    for k, key in enumerate([1, None, ("weave", "rows"), "weave.\0rows", ""]):
        yield case(f"load_scene.override_key.{k}",
                   lambda s, key=key: chainmail.load_scene(s, {key: 1}), ValueError, "")
    for k, value in enumerate([1, None, ["weave.rows=3"]]):
        yield case(f"load_scene.overrides_type.{k}",
                   lambda s, value=value: chainmail.load_scene(s, value), TypeError, "")


def simulation_cases():
    for k, backend in enumerate(["nonesuch", "", "plausible\0", "PLAUSIBLE", "all", " plausible"]):
        yield case(f"Simulation.backend.{k}",
                   lambda s, b=backend: chainmail.Simulation(scene(s), b), ValueError, "")
    for k, threads in enumerate([-1, -2**31, 4097, 10**6]):
        yield case(f"Simulation.threads.{k}",
                   lambda s, t=threads: chainmail.Simulation(scene(s), "plausible", threads=t),
                   ValueError, "threads")
    for k, value in enumerate(NUMBERS[:6] + ["x", None, [1]]):
        yield case(f"Simulation.knobs.dt.{k}",
                   lambda s, v=value: chainmail.Simulation(scene(s), "plausible", knobs={"dt": v}),
                   ValueError, "dt")
    knobs = {"iterations": [0, -1, 10**6, 1.5, float("nan"), "10"],
             "damping": [-1.0, float("nan"), float("inf"), 1e9]}
    for knob, values in knobs.items():
        for k, value in enumerate(values):
            yield case(f"Simulation.knobs.{knob}.{k}",
                       lambda s, n=knob, v=value: chainmail.Simulation(scene(s), "plausible",
                                                                       knobs={n: v}),
                       ValueError, knob)
    for k, knob in enumerate(["no_such_knob", "", "dt\0"]):
        yield case(f"Simulation.knobs.name.{k}",
                   lambda s, n=knob: chainmail.Simulation(scene(s), "plausible", knobs={n: 1}),
                   ValueError, "")
    for k, value in enumerate(TYPES[:4]):
        yield case(f"Simulation.threads_type.{k}",
                   lambda s, v=value: chainmail.Simulation(scene(s), "plausible", threads=v),
                   TypeError, "")


def step_cases():
    for k, n in enumerate([0, -1, -5, -2**62]):
        yield case(f"step.n.{k}", lambda s, n=n: sim(s).step(n=n), ValueError, "n: ")
    for k, dt in enumerate([0.0, -1e-3, float("nan"), float("inf"), float("-inf"), 1e9, 1.0,
                            5e-324, 1e-300, -0.0]):
        yield case(f"step.dt.{k}", lambda s, dt=dt: sim(s).step(dt=dt), ValueError, "dt: ")
    for k, value in enumerate(["1", [], {}, object(), 2**70, 1.5]):
        yield case(f"step.n_type.{k}", lambda s, v=value: sim(s).step(n=v), TypeError, "")
    for k, value in enumerate(["0.001", [], object()]):
        yield case(f"step.dt_type.{k}", lambda s, v=value: sim(s).step(dt=v), TypeError, "")


def render_cases():
    arguments = {"width": [0, -1, 15, 8193, 10**6], "height": [0, -100, 8193],
                 "samples": [-1, 17, 1000], "material": ["", "gold\0", "unobtainium"]}
    for name, values in arguments.items():
        for k, value in enumerate(values):
            yield case(f"render.{name}.{k}",
                       lambda s, n=name, v=value: chainmail.render([sim(s)], **{n: v}),
                       ValueError, name)
    yield case("render.empty", lambda s: chainmail.render([]), ValueError, "simulations")
    yield case("render.not_a_simulation", lambda s: chainmail.render([1]), TypeError, "")


def run_cases():
    texts = {"out": ["a\0b", "/dev/null", "/proc/self", "/"], "reference": ["nonesuch", "x\0"],
             "cache": ["c\0"]}
    for name, values in texts.items():
        for k, value in enumerate(values):
            yield case(f"run.{name}.{k}",
                       lambda s, n=name, v=value: chainmail.run(scene(s), backends=["plausible"],
                                                                **{n: v}),
                       ValueError, "")
    for k, backends in enumerate([["nonesuch"], ["plausible\0"], [""], ["all", "x"]]):
        yield case(f"run.backends.{k}",
                   lambda s, b=backends: chainmail.run(scene(s), backends=b), ValueError, "")
    for k, threads in enumerate([-1, 4097]):
        yield case(f"run.threads.{k}",
                   lambda s, t=threads: chainmail.run(scene(s), threads=t), ValueError, "threads")
    for k, threads in enumerate([-1, 4097]):
        yield case(f"sweep.threads.{k}",
                   lambda s, t=threads: chainmail.sweep(scene(s), ["weave.rows=4,5"], threads=t),
                   ValueError, "threads")
    for k, jobs in enumerate([0, -1, 257]):
        yield case(f"sweep.jobs.{k}",
                   lambda s, j=jobs: chainmail.sweep(scene(s), ["weave.rows=4,5"], jobs=j),
                   ValueError, "jobs")
    for k, vary in enumerate(["", "weave.rows", "weave.rows=", "no_such=1,2", "weave.rows=a,b",
                              "weave.rows=4\0"]):
        yield case(f"sweep.vary.{k}",
                   lambda s, v=vary: chainmail.sweep(scene(s), [v]),
                   ValueError, "")


CASES = [*scene_cases(), *simulation_cases(), *step_cases(), *render_cases(), *run_cases()]
_SCENES, _SIMS = {}, {}


def scene(path):
    if path not in _SCENES:
        _SCENES[path] = chainmail.load_scene(path, SMALL)
    return _SCENES[path]


def sim(path):
    if path not in _SIMS:
        _SIMS[path] = chainmail.Simulation(scene(path), "plausible", threads=1)
    return _SIMS[path]


def test_the_corpus_is_large():
    assert len(CASES) >= 150


def listing(folder):
    return sorted((root, tuple(sorted(files))) for root, _, files in os.walk(folder))


@pytest.mark.parametrize("call, error, token", CASES)
def test_refused(call, error, token, curtain, tmp_path, monkeypatch):
    if "render" in repr(call.__code__.co_names) and not hasattr(chainmail, "render"):
        pytest.skip("built without the renderer")
    monkeypatch.chdir(tmp_path)  # a default output folder would land here
    before = listing(tmp_path)
    with pytest.raises(error) as raised:
        call(curtain)
    message = str(raised.value)
    assert message
    if error is not TypeError:  # pybind11's lists the accepted signatures, one a line
        assert "\n" not in message.strip()
    assert token in message
    assert not message.startswith("render: render:")
    assert listing(tmp_path) == before
    if "sim" in call.__code__.co_names:  # a refused step changed nothing
        assert sim(curtain).steps == 0 and math.isfinite(sim(curtain).t)
