"""Tests of the Python package: every public function, its error paths,
and agreement with the Rust library it wraps."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import geopid

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
FLIP_TOML = os.path.join(ROOT, "scenes", "scenes", "paper-flip.toml")
# The command line to compare with: an xtask binary already built (CI's,
# given in XTASK) or `cargo xtask` from the checkout.
XTASK = [os.environ["XTASK"]] if os.environ.get("XTASK") else ["cargo", "xtask"]


# --- scenes -----------------------------------------------------------------


def test_scene_names_and_every_way_to_give_a_scene():
    names = geopid.scene_names()
    assert "paper-flip" in names and "hover-disturbed" in names
    by_name = geopid.load_scene("paper-flip")
    by_path = geopid.load_scene(FLIP_TOML)
    by_pathlike = geopid.load_scene(__import__("pathlib").Path(FLIP_TOML))
    text = by_name.to_toml()
    by_text = geopid.load_scene(text)
    assert by_path.to_toml() == by_pathlike.to_toml()
    assert by_text.to_toml() == text
    assert by_name.name == "paper-flip" and by_name.duration > 0
    # A dict in the scene schema (numpy values welcome).
    d = {"name": "dict-hover", "duration": np.float64(1.0),
         "vehicle": {"kind": "quadrotor", "inertia": np.array([0.6e-2, 0.6e-2, 1.02e-2])}}
    s = geopid.load_scene(d)
    assert s.name == "dict-hover" and s.duration == 1.0
    assert "Scene(" in repr(s)


def test_scene_errors_carry_key_and_location():
    with pytest.raises(geopid.SceneError) as e:
        geopid.load_scene("no-such-scene")
    assert "no-such-scene" in str(e.value)
    bad = geopid.load_scene("paper-flip").to_toml().replace("duration = ", "duration = -", 1)
    with pytest.raises(geopid.SceneError) as e:
        geopid.load_scene(bad)
    assert e.value.key == "duration"
    assert e.value.location.startswith("<string>:")
    assert isinstance(e.value, ValueError)
    with pytest.raises(geopid.SceneError) as e:
        geopid.load_scene({"name": "x", "duration": 1.0, "bogus": 3})
    assert "bogus" in str(e.value)
    with pytest.raises(TypeError):
        geopid.load_scene(42)


def test_overrides_land_and_bad_ones_name_the_key():
    s = geopid.load_scene("paper-flip", integrator="rk4", dt=2e-4, duration=1.5,
                          scalar="f32", backend="glam", no_integral=True)
    toml = s.to_toml()
    assert 'kind = "rk4"' in toml and "dt = 0.0002" in toml
    assert 'scalar = "f32"' in toml and 'backend = "glam"' in toml
    assert s.duration == 1.5
    for kw, key in [({"dt": -1.0}, "integrator.dt"), ({"tol": math.nan}, "integrator.tol"),
                    ({"integrator": "rk5"}, "integrator.kind"), ({"scalar": "f16"}, "scalar"),
                    ({"backend": "eigen"}, "backend"), ({"sample": 0.0}, "record.sample")]:
        with pytest.raises(geopid.SceneError) as e:
            geopid.load_scene("paper-flip", **kw)
        assert e.value.key == key, (kw, str(e.value))
    with pytest.raises(TypeError):
        geopid.load_scene("paper-flip", stepsize=1e-3)


# --- runs -------------------------------------------------------------------


def test_run_returns_arrays_of_the_documented_shapes():
    r = geopid.run("paper-flip", duration=2.0, sample=0.01)
    n = 201
    assert r.t.shape == (n,) and np.all(np.diff(r.t) > 0)
    for name in ("x", "v", "omega", "moment", "xd", "omega_d", "e_att", "e_pos"):
        assert getattr(r, name).shape == (n, 3), name
    assert r.R.shape == (n, 3, 3) and r.Rd.shape == (n, 3, 3)
    assert r.rotors.shape == (n, 4)
    assert len(r.mode) == n and r.segment.shape == (n,)
    # The flip switches from attitude to position mode at 0.4 s.
    assert len(r.switches) == 1 and abs(r.switches[0][0] - 0.4) < 1e-12
    assert r.termination == {"kind": "completed", "t": None}
    assert r.health == []
    # R near SO(3): rk4 drifts (1.6e-10 here), within the health bound
    # of 1e-6 that `health` reports against; the group-preserving LGVI
    # (samples interpolated on the group) keeps RᵀR = I to rounding.
    def off_group(R):
        return np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max()
    assert off_group(r.R) < 1e-6
    assert off_group(geopid.run("paper-flip", duration=2.0, integrator="lgvi").R) < 1e-13
    # The rotor thrusts add up to the commanded thrust (allocation).
    assert np.allclose(r.rotors.sum(axis=1), r.thrust, rtol=1e-9, atol=1e-9)
    assert "samples" in repr(r)


def test_run_matches_the_command_line_csv(tmp_path):
    """The package and `cargo xtask run` give the same CSV, byte for byte."""
    ours = tmp_path / "py.csv"
    geopid.run("paper-flip", duration=1.0, csv=ours, mcap=tmp_path / "py.mcap")
    assert (tmp_path / "py.mcap").stat().st_size > 1000
    cli = tmp_path / "cli.csv"
    cmd = XTASK + ["run", "paper-flip", "--duration", "1", "--csv", str(cli)]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        pytest.skip(f"cargo xtask unavailable here: {done.stderr[-300:]}")
    assert ours.read_bytes() == cli.read_bytes()


def test_the_module_command_line_writes_what_run_writes(tmp_path):
    """`python -m geopid run` is `geopid.run` with the command line's
    options: the same CSV bytes, a summary line, typed exit statuses."""
    ours = tmp_path / "py.csv"
    geopid.run("paper-flip", duration=0.5, integrator="lgvi", csv=ours)
    cli = tmp_path / "cli.csv"
    done = subprocess.run(
        [sys.executable, "-m", "geopid", "run", "paper-flip", "--duration", "0.5",
         "--integrator", "lgvi", "--csv", str(cli)],
        capture_output=True, text=True, timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("completed at t = 0.5 s: Ψ = "), done.stdout
    assert ours.read_bytes() == cli.read_bytes()
    bad = subprocess.run(
        [sys.executable, "-m", "geopid", "run", "paper-flip", "--integrator", "leapfrog"],
        capture_output=True, text=True, timeout=300,
    )
    assert bad.returncode == 2 and "leapfrog" in bad.stderr, bad.stderr
    listed = subprocess.run([sys.executable, "-m", "geopid", "scenes"],
                            capture_output=True, text=True, timeout=300)
    assert "paper-flip" in listed.stdout.split()


def test_output_paths_fail_before_the_run(tmp_path):
    """A path that cannot be written is refused before anything runs (a
    long run does not end in a lost result), naming the argument."""
    with pytest.raises(OSError) as e:
        geopid.run("paper-flip", duration=100.0, csv=tmp_path / "no" / "such" / "dir.csv")
    assert e.value.field == "csv"
    assert "no/such" in str(e.value)
    with pytest.raises(OSError) as e:
        geopid.run("paper-flip", duration=100.0, csv=tmp_path / "a", mcap=tmp_path / "." / "a")
    assert e.value.field == "mcap" and "same file as csv" in str(e.value)
    with pytest.raises(OSError) as e:
        geopid.run("paper-flip", duration=100.0, mcap=tmp_path)
    assert e.value.field == "mcap" and "directory" in str(e.value)
    assert not (tmp_path / "a").exists()


def test_every_scalar_and_backend_agree():
    runs = [geopid.run("hover-disturbed", duration=1.0, scalar=s, backend=b)
            for s in ("f64", "f32") for b in ("nalgebra", "glam")]
    for r in runs[1:2]:
        assert np.abs(r.x - runs[0].x).max() < 1e-12
    for r in runs[2:]:
        # f32 rounding (ε = 1.2e-7) over 1 s of flight.
        assert np.abs(r.x - runs[0].x).max() < 1e-4


def test_to_pandas_only_when_pandas_is_there():
    r = geopid.run("paper-flip", duration=0.1)
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError):
            r.to_pandas()
        return
    df = r.to_pandas()
    assert len(df) == len(r.t) and "R22" in df.columns and "rotor3" in df.columns


def test_a_non_finite_reference_is_a_scene_error_naming_the_key():
    d = {
        "name": "nan-reference",
        "duration": 1.0,
        "plan": [{"mode": "position",
                  "position": {"kind": "hold", "x": [0.0, 0.0, float("nan")], "b1d": [1.0, 0.0, 0.0]}}],
    }
    with pytest.raises(geopid.SceneError) as e:
        geopid.run(d)
    assert e.value.key == "x" and "must be finite" in str(e.value)
    assert e.value.location.startswith("<dict>:")


def test_the_guard_raises_or_returns_by_flag():
    # The flip turns at up to ~20 rad/s: a 5 rad/s limit stops it.
    with pytest.raises(geopid.DivergedError) as e:
        geopid.run("paper-flip", guard={"omega": 5.0})
    term = e.value.termination
    assert term["kind"] == "diverged" and term["what"] == "omega"
    assert 5.0 < term["value"] < 30.0 and 0.0 < e.value.t < 0.4
    assert isinstance(e.value, geopid.SimulationError)
    partial = e.value.result
    assert partial.t[-1] <= e.value.t + 1e-12
    assert np.linalg.norm(partial.omega[:-1], axis=1).max() <= 5.0 + 1e-9
    r = geopid.run("paper-flip", guard={"omega": 5.0}, raise_on_divergence=False)
    assert r.termination == term
    with pytest.raises(ValueError, match="guard"):
        geopid.run("paper-flip", guard={"omega": -1.0})
    with pytest.raises(ValueError, match="unknown key `spin`"):
        geopid.run("paper-flip", guard={"spin": 1.0})


def test_a_diverging_state_raises_simulation_error_with_its_time():
    """Never a silent NaN array: a state that overflows in the next step
    is an error naming the time and the field (the Rust message)."""
    sim = geopid.Simulation("hover-disturbed", duration=2.0)
    sim.advance_to(0.5)
    sim.set_state(omega=[1e200, 0.0, 0.0])
    with pytest.raises(geopid.SimulationError) as e:
        sim.advance_to(1.0)
    assert e.value.t == 0.5
    assert "t = 0.5" in str(e.value) and "not finite" in str(e.value)
    assert isinstance(e.value, RuntimeError)


# --- stepping ---------------------------------------------------------------


def test_pieces_equal_one_run_bit_for_bit():
    one = geopid.run("paper-flip", duration=3.0)
    sim = geopid.Simulation("paper-flip", duration=3.0)
    for t in np.linspace(0.0, 3.0, 8)[1:]:
        sim.advance_to(t)
    assert sim.termination == {"kind": "completed", "t": None}
    pieces = sim.finish()
    for name in ("t", "x", "v", "R", "omega", "psi", "thrust", "moment"):
        assert np.array_equal(getattr(pieces, name), getattr(one, name)), name


def test_state_and_set_state():
    sim = geopid.Simulation("hover-disturbed", duration=4.0)
    sim.advance_to(1.0)
    s = sim.state
    assert abs(s["t"] - 1.0) < 1e-12 and s["R"].shape == (3, 3)
    assert s["integrals"].shape == (6,) and s["mode"] == "position"
    sim.set_state(omega=s["omega"] + [3.0, 0.0, 0.0])
    assert np.allclose(sim.state["omega"], s["omega"] + [3.0, 0, 0])
    sim.advance_to(1.2)
    assert sim.output().psi.max() > 1e-4  # the kick shows
    sim.advance_to(4.0)
    r = sim.finish()
    assert r.psi[-1] < 1e-3  # and is recovered from
    with pytest.raises(RuntimeError):
        sim.advance_to(5.0)  # finished


def test_set_state_errors_name_the_field():
    sim = geopid.Simulation("hover-disturbed", duration=1.0)
    with pytest.raises(ValueError, match="omega"):
        sim.set_state(omega=[1.0, 2.0])
    with pytest.raises(ValueError, match=r"x: NaN is not finite"):
        sim.set_state(x=[0.0, math.nan, 0.0])
    with pytest.raises(ValueError, match="integrals"):
        sim.set_state(integrals=np.zeros(4))
    with pytest.raises(TypeError):
        sim.set_state(position=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError) as e:
        sim.advance_to(math.nan)
    assert e.value.field == "advance_to"
    with pytest.raises(TypeError):
        geopid.Simulation("hover-disturbed", stepsize=0.1)


# --- a Python reference in the loop ------------------------------------------


def test_a_callable_reference_equal_to_the_scene_gives_the_same_run():
    calls = []

    def hold(t):
        calls.append(t)
        return ((0.0, 0.0, 0.0),)  # x_d; the rest zero, b1d = e1

    plain = geopid.run("hover-disturbed", duration=2.0)
    ours = geopid.run("hover-disturbed", duration=2.0, reference=hold)
    assert len(calls) > ours.steps  # evaluated at every stage, and for the log
    for name in ("t", "x", "R", "omega", "thrust"):
        assert np.array_equal(getattr(plain, name), getattr(ours, name)), name


def test_a_callable_reference_is_tracked():
    """A circle of radius 1 m at 0.5 rad/s, 1 m up, with its derivatives
    up to snap and the heading along it: after 15 s the error is small."""
    w, r = 0.5, 1.0

    def circle(t):
        c, s = math.cos(w * t), math.sin(w * t)
        x = (r * c, r * s, -1.0)
        v = (-r * w * s, r * w * c, 0.0)
        a = (-r * w**2 * c, -r * w**2 * s, 0.0)
        j = (r * w**3 * s, -r * w**3 * c, 0.0)
        sn = (r * w**4 * c, r * w**4 * s, 0.0)
        return {"x": x, "v": v, "a": a, "jerk": j, "snap": sn}

    out = geopid.run("hover-disturbed", duration=20.0, reference=circle)
    late = out.t > 15.0
    assert out.ex[late].max() < 0.02, out.ex[late].max()
    assert np.allclose(out.xd[-1], circle(out.t[-1])["x"], atol=1e-12)
    sim = geopid.Simulation("hover-disturbed", reference=circle, duration=2.0)
    sim.advance_to(2.0)
    assert np.array_equal(sim.finish().x, geopid.run("hover-disturbed", duration=2.0, reference=circle).x)


def test_a_callable_reference_error_is_raised_as_itself():
    def boom(t):
        if t > 0.5:
            raise ZeroDivisionError("boom at %g" % t)
        return ((0.0, 0.0, 0.0),)

    with pytest.raises(ZeroDivisionError, match="boom at"):
        geopid.run("hover-disturbed", duration=1.0, reference=boom)
    sim = geopid.Simulation("hover-disturbed", reference=boom, duration=1.0)
    sim.advance_to(0.4)
    with pytest.raises(ZeroDivisionError):
        sim.advance_to(1.0)
    for bad, msg in [(lambda t: ((0.0, 0.0),), "`x` is not 3 numbers"),
                     (lambda t: {"pos": (0.0, 0.0, 0.0)}, "unknown key `pos`"),
                     (lambda t: 3.0, "expected a tuple"),
                     (lambda t: (), "0 vectors")]:
        with pytest.raises(ValueError, match=msg):
            geopid.run("hover-disturbed", duration=0.1, reference=bad)


# --- controllers over arrays ------------------------------------------------


def _hover_states(n, rng):
    R = np.tile(np.eye(3), (n, 1, 1))
    return {
        "x": rng.normal(size=(n, 3)),
        "v": rng.normal(size=(n, 3)),
        "R": R,
        "omega": rng.normal(size=(n, 3)),
    }


def test_position_control_at_the_equilibrium_is_hover():
    n = 5
    st = {"x": np.zeros((n, 3)), "v": np.zeros((n, 3)), "R": np.tile(np.eye(3), (n, 1, 1)),
          "omega": np.zeros((n, 3))}
    out = geopid.position_control(st)
    m, g = 0.755, 9.81
    assert np.allclose(out["thrust"], m * g, rtol=1e-14)
    assert np.abs(out["moment"]).max() < 1e-14
    assert np.allclose(out["Rc"], np.eye(3))
    assert out["psi"].shape == (n,) and out["e_x"].shape == (n, 3)


def test_position_control_rows_match_single_calls_and_gains_matter():
    rng = np.random.default_rng(3)
    st = _hover_states(16, rng)
    ref = {"x": [1.0, 0.0, -1.0], "b1d": [1.0, 0.0, 0.0]}
    all_rows = geopid.position_control(st, ref)
    for i in (0, 7, 15):
        one = geopid.position_control({k: v[i:i + 1] for k, v in st.items()}, ref)
        assert np.array_equal(one["moment"][0], all_rows["moment"][i])
        assert one["thrust"][0] == all_rows["thrust"][i]
    softer = geopid.position_control(st, ref, gains={"k_x": 1.0})
    assert not np.allclose(softer["thrust"], all_rows["thrust"])
    # e_x is x − x_d, whatever the gains.
    assert np.allclose(all_rows["e_x"], st["x"] - ref["x"])
    # Over many states the rows are split across threads: the same values.
    big = _hover_states(6000, rng)
    whole = geopid.position_control(big, ref)
    for lo in range(0, 6000, 1000):
        part = geopid.position_control({k: v[lo:lo + 1000] for k, v in big.items()}, ref)
        for name in ("thrust", "moment", "Rc", "omega_c_dot"):
            assert np.array_equal(part[name], whole[name][lo:lo + 1000]), name
    # A selection returns just those, with the same values.
    some = geopid.position_control(st, ref, outputs=["thrust", "moment"])
    assert set(some) == {"thrust", "moment"}
    assert np.array_equal(some["moment"], all_rows["moment"])
    with pytest.raises(ValueError, match="unknown `torque`"):
        geopid.position_control(st, ref, outputs=["torque"])


def test_attitude_control_against_the_closed_form():
    # R = Exp(θ e1), Ω = 0, R_d = I: e_R = ½ (R_dᵀR − RᵀR_d)^∨ = sin θ e1,
    # Ψ = 1 − cos θ, M = −k_R e_R (plus zero gyroscopic terms).
    th = np.array([0.1, 0.5, 1.0, 2.0])
    c, s = np.cos(th), np.sin(th)
    R = np.zeros((4, 3, 3))
    R[:, 0, 0] = 1.0
    R[:, 1, 1], R[:, 1, 2], R[:, 2, 1], R[:, 2, 2] = c, -s, s, c
    out = geopid.attitude_control({"R": R, "omega": np.zeros((4, 3))}, gains={"k_r": 2.0})
    assert np.allclose(out["e_R"][:, 0], s, atol=1e-15)
    assert np.allclose(out["psi"], 1 - c, atol=1e-15)
    assert np.allclose(out["moment"][:, 0], -2.0 * s, atol=1e-14)


def test_controller_errors_name_the_field_and_row():
    rng = np.random.default_rng(0)
    st = _hover_states(4, rng)
    with pytest.raises(ValueError, match=r"states.v: shape \(3, 3\), expected \(4, 3\)"):
        geopid.position_control(dict(st, v=np.zeros((3, 3))))
    with pytest.raises(ValueError, match="`x` is missing"):
        geopid.position_control({k: v for k, v in st.items() if k != "x"})
    with pytest.raises(ValueError, match="unknown key `pos`"):
        geopid.position_control(dict(st, pos=np.zeros((4, 3))))
    with pytest.raises(ValueError, match="gains"):
        geopid.position_control(st, gains={"k_q": 1.0})
    with pytest.raises(ValueError, match="mass"):
        geopid.position_control(st, params={"mass": -1.0})
    bad = dict(st, omega=st["omega"].copy())
    bad["omega"][2, 1] = math.nan
    with pytest.raises(ValueError) as e:
        geopid.position_control(bad)
    assert e.value.row == 2 and e.value.field == "state.omega"
    badref = {"jerk": np.full((4, 3), math.inf)}
    with pytest.raises(ValueError) as e:
        geopid.position_control(st, badref)
    assert e.value.field.startswith("reference.")
    with pytest.raises(ValueError, match="states.R"):
        geopid.attitude_control({"R": np.zeros((2, 3)), "omega": np.zeros((2, 3))})


# --- Monte Carlo ------------------------------------------------------------


def test_montecarlo_rows_match_the_command_line(tmp_path):
    rows = geopid.montecarlo("attitude", samples=12, seed=1, csv=tmp_path / "s.csv")
    assert rows.shape == (12,) and list(rows["index"]) == list(range(12))
    assert set(rows["status"]) <= {"converged", "deadline", "diverged", "error"}
    assert rows["converged"].sum() >= 10  # the paper's attitude law: almost all
    text = (tmp_path / "s.csv").read_text()
    assert text.splitlines()[0] == geopid._geopid.montecarlo_header()
    # The same rows from any thread count and from a subset of indices.
    again = geopid.montecarlo("attitude", samples=12, seed=1, threads=1)
    assert np.array_equal(rows["t_converge"], again["t_converge"], equal_nan=True)
    part = geopid.montecarlo("attitude", seed=1, indices=[3, 9])
    assert np.array_equal(part["angle"], rows["angle"][[3, 9]])
    out = tmp_path / "cli"
    cmd = XTASK + ["montecarlo", "--experiment", "attitude", "--samples", "12",
           "--seed", "1", "--out", str(out)]
    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        pytest.skip(f"cargo xtask unavailable here: {done.stderr[-300:]}")
    assert (out / "samples.csv").read_text() == text


def test_montecarlo_errors():
    with pytest.raises(ValueError, match="experiment"):
        geopid.montecarlo("yaw", samples=1)
    with pytest.raises(ValueError, match="unknown setting `omega`"):
        geopid.montecarlo("attitude", samples=1, omega=3.0)
    with pytest.raises(ValueError, match="hold"):
        geopid.montecarlo("attitude", samples=1, hold=-1.0)
    # A zero step would never end: refused before any sample runs.
    with pytest.raises(ValueError, match="must be finite and > 0") as e:
        geopid.montecarlo("attitude", samples=1, dt=0.0)
    assert e.value.field == "dt"
    with pytest.raises(ValueError, match="threads"):
        geopid.montecarlo("attitude", samples=1, threads=0)


def test_montecarlo_on_lanes_equals_the_scalar_rows_without_event_location():
    """The lane path runs each sample's operations in the scalar path's
    order, without locating sat′ crossings: class, time to converge and
    step count equal the scalar rows with ``locate_events=False``."""
    lanes = geopid.montecarlo("position", samples=40, seed=3, lanes=True)
    scalar = geopid.montecarlo("position", samples=40, seed=3, locate_events=False)
    assert list(lanes["status"]) == list(scalar["status"])
    assert np.array_equal(lanes["steps"], scalar["steps"])
    assert np.array_equal(lanes["t_converge"], scalar["t_converge"], equal_nan=True)
    with pytest.raises(ValueError, match="dopri only") as e:
        geopid.montecarlo("attitude", samples=1, lanes=True, integrator="rk4")
    assert e.value.field == "integrator"


def _both_builds_installed():
    from geopid import _native
    import importlib.util
    return (_native._baseline.cpu_has_x86_64_v3()
            and importlib.util.find_spec("geopid._geopid_x86_64_v3") is not None)


def _in_fresh_interpreter(code, *args, instruction_set=None):
    env = dict(os.environ)
    env.pop("GEOPID_INSTRUCTION_SET", None)
    if instruction_set is not None:
        env["GEOPID_INSTRUCTION_SET"] = instruction_set
    return subprocess.run([sys.executable, "-c", code, *map(str, args)], env=env,
                          capture_output=True, text=True, cwd=os.path.dirname(ROOT))


def test_the_two_builds_of_a_wheel_fly_the_same_samples(tmp_path):
    """A wheel carries the extension built for any x86-64 and for
    x86-64-v3 (AVX2, FMA): the lanes' instructions differ, the samples may
    not. CI sets GEOPID_REQUIRE_BOTH_BUILDS=1 for its wheel, where a skip
    would hide a wheel that lost one build."""
    if not _both_builds_installed():
        if os.environ.get("GEOPID_REQUIRE_BOTH_BUILDS") == "1":
            pytest.fail("GEOPID_REQUIRE_BOTH_BUILDS=1, but the x86-64-v3 build is not installed or this CPU lacks it")
        pytest.skip("one build of the extension here (a build from a checkout), or a CPU without x86-64-v3")
    code = ("import geopid, sys\n"
            "geopid.montecarlo('position', samples=1000, seed=1, lanes=True, csv=sys.argv[1])\n"
            "print(geopid.instruction_set())")
    for want in ["baseline", "x86-64-v3", None]:
        done = _in_fresh_interpreter(code, tmp_path / f"{want}.csv", instruction_set=want)
        assert done.returncode == 0, done.stderr[-500:]
        # Unset, the CPU decides: this one has x86-64-v3.
        assert done.stdout.strip() == (want or "x86-64-v3")
    base = (tmp_path / "baseline.csv").read_bytes()
    assert len(base.splitlines()) == 1001
    assert (tmp_path / "x86-64-v3.csv").read_bytes() == base
    assert (tmp_path / "None.csv").read_bytes() == base


def test_an_installation_with_one_build_imports_it():
    """A build from a checkout (``pip install ./python``) has no
    x86-64-v3 module beside the baseline one: ``import geopid`` takes the
    one there is (the wheel in CI has both, so the absence is simulated)."""
    code = (
        "import importlib.abc, sys\n"
        "class Hide(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name == 'geopid._geopid_x86_64_v3':\n"
        "            raise ModuleNotFoundError(f'No module named {name!r}', name=name)\n"
        "        return None\n"
        "sys.meta_path.insert(0, Hide())\n"
        "import geopid\n"
        "from geopid import _native\n"
        "assert _native.ext is _native._baseline\n"
        "print(geopid.instruction_set(), geopid.run('paper-flip', duration=0.1).t[-1])"
    )
    done = _in_fresh_interpreter(code)
    assert done.returncode == 0, done.stderr[-800:]
    assert done.stdout.split()[0] in ("baseline", "x86-64-v3")


def test_a_wrong_instruction_set_request_is_refused_naming_the_variable():
    done = _in_fresh_interpreter("import geopid", instruction_set="avx9")
    assert done.returncode != 0
    assert "GEOPID_INSTRUCTION_SET='avx9'" in done.stderr
    assert geopid.instruction_set() in ("baseline", "x86-64-v3")


@pytest.mark.parametrize("call", [
    "geopid.montecarlo('position', samples=100000, seed=1, lanes=True)",
    "geopid.montecarlo('position', samples=100000, seed=1)",
    "geopid.run('hover-disturbed', duration=1e5, sample=1.0)",
    "geopid.run('hover-disturbed', duration=1e5, sample=1.0, reference=lambda t: ((0.0, 0.0, 0.0),))",
])
def test_ctrl_c_interrupts_a_long_run_cleanly(call):
    """SIGINT while a long study or run goes on (with the lock released,
    or with a Python reference on this thread): KeyboardInterrupt within
    a second or so, and the interpreter goes on."""
    code = (
        "import geopid, signal, threading, os, time\n"
        # A shell without job control starts background commands with
        # SIGINT ignored, and Python keeps that: restore Python's handler.
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()\n"
        "t = time.time()\n"
        "try:\n"
        f"    {call}\n"
        "    print('finished')\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted after', round(time.time() - t, 1))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("interrupted after"), done.stdout
    assert float(done.stdout.split()[-1]) < 5.0


def test_wind_reaches_the_multirotor_and_its_log():
    # gusty-hover: RotorPy's crazyflie in Dryden turbulence (σ = 1 m/s).
    r = geopid.run("gusty-hover", duration=2.0)
    assert r.wind.shape == (len(r.t), 3)
    # Over 2 s the gusts reach tenths of a m/s on some axis.
    assert np.abs(r.wind).max() > 0.1
    assert r.vehicle_states.shape == (len(r.t), 4)  # rotor speeds, rad/s
    assert 1000.0 < r.vehicle_states.max() < 2500.0
    # The same scene without wind holds the point far better.
    text = geopid.load_scene("gusty-hover").to_toml()
    head, tail = text.split("[wind]\n", 1)
    rest = tail[tail.index("\n[") + 1:] if "\n[" in tail else ""
    calm = head + '[wind]\nkind = "constant"\nvelocity = [0.0, 0.0, 0.0]\n' + rest
    c = geopid.run(calm, duration=2.0)
    assert np.abs(c.wind).max() == 0.0
    assert c.ex.max() < 0.5 * r.ex.max()


def test_a_bad_wind_parameter_names_its_key():
    text = geopid.load_scene("gusty-hover").to_toml().replace("speed = 5.0", "speed = 0.0")
    with pytest.raises(geopid.SceneError) as e:
        geopid.load_scene(text)
    assert e.value.key == "wind.speed", str(e.value)


def _with_gain(scene, key, value):
    """The scene with `gains.<key>` set, through its TOML text."""
    import re

    text = scene.to_toml()
    section = text.index("[gains]")
    head, tail = text[:section], text[section:]
    tail, n = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value!r}", tail, count=1)
    assert n == 1, key
    return geopid.load_scene(head + tail)


def test_gradient_equals_central_differences():
    # Two seconds of DiffTune's circle; the exact gradient against central
    # differences of the value itself at h = 1e-4 of the gain: truncation
    # ~h^2 relative, rounding ~1e-16 / 1e-4 of the cost, both far below
    # the 1e-6 allowed.
    scene = geopid.load_scene("difftune-circle", duration=2.0)
    value, g = geopid.gradient(scene, ["gains.k_x", "gains.k_omega"])
    assert g.shape == (2,)
    for i, key in enumerate(["k_x", "k_omega"]):
        k0 = {"k_x": 16.0, "k_omega": 2.54}[key]
        h = 1e-4 * k0
        up, _ = geopid.gradient(_with_gain(scene, key, k0 + h), ["gains.k_x"])
        down, _ = geopid.gradient(_with_gain(scene, key, k0 - h), ["gains.k_x"])
        fd = (up - down) / (2 * h)
        assert abs(g[i] - fd) <= 1e-6 * abs(fd), (key, g[i], fd)
    # The value is the plain run's cost, bit for bit.
    again, _ = geopid.gradient(scene, ["vehicle.mass"])
    assert again == value
    with pytest.raises(geopid.SceneError, match="gains.k_q"):
        geopid.gradient(scene, ["gains.k_q"])
    with pytest.raises(ValueError, match="between 1 and 4"):
        geopid.gradient(scene, [])


def test_tune_lowers_difftunes_error_3_5x_within_the_thrust_limit():
    out = geopid.tune("difftune-circle", gradients=6)
    scene = out["scene"]
    rmse = np.sqrt(out["cost"] / scene.duration)
    final = math.sqrt(out["final_cost"] / scene.duration)
    assert rmse[0] / final >= 3.5, (rmse, final)
    assert np.all(np.diff(out["cost"]) < 0)
    weight = 4.34 * 9.81
    assert np.all(out["max_thrust"] <= 2.0 * weight)
    assert out["gains"].shape == (len(rmse), 4)
    assert list(out["names"]) == ["gains.k_x", "gains.k_v", "gains.k_r", "gains.k_omega"]
    assert out["gains"][0].tolist() == pytest.approx([16.0, 5.6, 8.81, 2.54], rel=1e-15)
    assert abs(geopid.gradient(scene, ["gains.k_x"])[0] - out["final_cost"]) == 0.0


def test_tune_averages_the_cost_over_noise_seeds():
    scene = geopid.load_scene("figure-eight-estimated", duration=2.0, seed=7)
    out = geopid.tune(scene, gradients=1, noise_seeds=3, thrust_to_weight=None)
    # The first iteration's cost is the mean of the scene's cost on seeds
    # 7, 8 and 9, each a plain run's (as the gradient reports it).
    each = [
        geopid.gradient(geopid.load_scene(scene, seed=s), ["gains.k_x"])[0] for s in (7, 8, 9)
    ]
    assert len(set(each)) == 3, "the seeds fly different noise"
    assert out["cost"][0] == pytest.approx(sum(each) / 3.0, rel=1e-14)


# --- sensors ----------------------------------------------------------------


def test_flying_on_mocap_gives_measurements_and_the_estimate():
    kw = dict(control_rate=100.0, sensors="rotorpy", estimator="mocap", seed=3, duration=2.0)
    res = geopid.run("figure-eight", **kw)
    mocap = res.measurements["mocap"]
    # One frame per 10 ms from t = 0, each arriving when taken (no latency).
    assert mocap["x"].shape == (201, 3) and mocap["R"].shape == (201, 3, 3)
    assert np.array_equal(mocap["t"], mocap["arrival"])
    assert res.measurements["imu"]["accel"].shape == (201, 3)
    assert res.estimate is not None and res.estimate["x"].shape == res.x.shape
    # Mocap noise: σ = √(100/2)·0.0005 m about the truth.
    noise = mocap["x"] - np.array([res.x[int(round(t / 0.01))] for t in mocap["t"]])
    assert 0.5 < noise.std() / (math.sqrt(50.0) * 0.0005) < 1.5
    again = geopid.run("figure-eight", **kw)
    assert np.array_equal(again.x, res.x), "the same seed flies the same"
    other = geopid.run("figure-eight", **dict(kw, seed=4))
    assert not np.array_equal(other.x, res.x)
    plain = geopid.run("figure-eight", duration=2.0)
    assert plain.measurements == {} and plain.estimate is None


def test_the_invariant_ekf_beats_the_raw_mocap_on_the_figure_eight():
    res = geopid.run("figure-eight-estimated", duration=4.0)
    again = geopid.run("figure-eight-estimated", duration=4.0, estimator="mocap")
    tail = res.t >= 2.0

    def rms(r):
        d = r.estimate["x"][tail] - r.x[tail]
        return math.sqrt((d * d).sum(axis=1).mean())

    # The mocap's σ is 1 cm per axis (1.7 cm in norm); the filter that
    # fuses the 1 kHz IMU with it sits several times below.
    assert rms(res) < 0.005 < 0.01 < rms(again)
    # The filter's own σ (position, velocity, attitude, biases) and NIS.
    assert res.estimate["sigma"].shape == (res.t.size, 15)
    assert 1e-4 < res.estimate["sigma"][-1, 0] < 5e-3
    assert np.isfinite(res.estimate["nis"][-1])
    # The last mocap correction's innovation: 1 cm frames against an
    # estimate of a few mm, so centimetres at most, and its NIS is the
    # innovation weighed by its covariance (positive).
    innov = res.estimate["innovation"]
    assert innov.shape == (res.t.size, 6) and np.all(np.isfinite(innov[-1]))
    assert np.abs(innov[-1, :3]).max() < 0.05
    comp = geopid.run("figure-eight-estimated", duration=4.0, estimator="complementary")
    assert comp.estimate is not None and "sigma" not in comp.estimate


def test_a_bad_sensor_setting_names_its_key():
    with pytest.raises(geopid.SceneError) as e:
        geopid.run("figure-eight", sensors="vicon")
    assert e.value.key == "sensors.preset" and "vicon" in str(e.value)
    with pytest.raises(geopid.SceneError) as e:
        geopid.run("figure-eight", sensors="rotorpy", estimator="mocap")
    assert e.value.key == "estimator.kind" and "sampled" in str(e.value)
    with pytest.raises(geopid.SceneError):
        geopid.run("figure-eight", estimator="kalman")


def test_loop_rates_fly_the_crazyflie_stabilizer_and_a_bad_name_is_refused():
    res = geopid.run("figure-eight", loop_rates="crazyflie", duration=2.0)
    # Estimator, attitude and position at 1 kHz, 500 Hz and 100 Hz: still on
    # the curve, on another trajectory than one rate at 500 Hz.
    assert res.ex[-1] < 0.1
    single = geopid.run("figure-eight", control_rate=500.0, duration=2.0)
    assert not np.array_equal(single.x, res.x)
    with pytest.raises(geopid.SceneError) as e:
        geopid.run("figure-eight", loop_rates="px4")
    assert e.value.key == "control.loop_rates" and "px4" in str(e.value)


def test_minsnap_returns_its_pieces_and_names_bad_input():
    square = [[0, 0, -1], [1, 0, -1], [1, 1, -1.5], [0, 1, -1]]
    # Inside the 6.47 s it lasts: after its end it holds the last point,
    # where the snap (free at the ends) drops to zero.
    t = np.linspace(0.0, 6.4, 3201)
    out = geopid.minsnap(square, yaw=[0, 1, 2, 3], mean_speed=0.5, sample=t)
    lengths = np.linalg.norm(np.diff(np.array(square, float), axis=0), axis=1)
    # RotorPy's timing: each segment's length over the mean speed.
    np.testing.assert_allclose(out["durations"], lengths / 0.5, rtol=1e-15)
    assert out["coefficients"].shape == (3, 4, 8)
    # Through the points at the piece boundaries; at the end v, a and jerk
    # are zero (the snap is free there).
    ends = np.concatenate([[0.0], np.cumsum(out["durations"])])
    again = geopid.minsnap(square, yaw=[0, 1, 2, 3], mean_speed=0.5, sample=ends)
    np.testing.assert_allclose(again["x"][:, 0, :], square, atol=1e-12)
    np.testing.assert_allclose(again["yaw"][:, 0], [0, 1, 2, 3], atol=1e-12)
    assert np.abs(again["x"][-1, 1:4, :]).max() < 1e-12
    # Each derivative is the slope of the one below it: central differences
    # at h = 2 ms agree to O(h²) times the next derivatives' size (< 1e-3).
    x = out["x"]
    for d in range(4):
        fd = np.gradient(x[:, d, :], t, axis=0)[1:-1]
        assert np.abs(fd - x[1:-1, d + 1, :]).max() < 1e-3 * (1 + np.abs(x[:, d + 1]).max())
    # The Crazyflie file: one row per piece, y, z and yaw negated (z up).
    rows = np.array([[float(c) for c in line.rstrip(",").split(",")]
                     for line in out["pptraj"].splitlines()[1:]])
    np.testing.assert_array_equal(rows[:, 0], out["durations"])
    sign = np.array([1, -1, -1, -1])[None, :, None]
    np.testing.assert_array_equal(rows[:, 1:].reshape(3, 4, 8), sign * out["coefficients"])
    with pytest.raises(ValueError) as e:
        geopid.minsnap([[0, 0, 0], [1, float("nan"), 0]])
    assert e.value.field == "waypoints[1].y"
    with pytest.raises(ValueError) as e:
        geopid.minsnap(square, times=[0, 1, 1, 2])
    assert e.value.field == "times[2]"
    with pytest.raises(ValueError, match="at most one"):
        geopid.minsnap(square, times=[0, 1, 2, 3], mean_speed=1.0)


def test_a_mission_lists_its_contacts_and_a_hard_drop_is_a_crash():
    r = geopid.run("mission-takeoff-waypoints-land")
    assert r.termination == {"kind": "completed", "t": None}
    ups = [c for c in r.contacts if not c[2]]
    downs = [c for c in r.contacts if c[2]]
    # The four feet let go early in the take-off; the landing comes down
    # at its 0.3 m/s descent rate, under the scene's 0.5 m/s crash speed.
    assert len(ups) >= 4 and all(c[0] < 0.01 for c in ups[:4])
    assert abs(downs[0][3] - 0.3) < 3e-3 and all(c[3] < 0.5 for c in downs)
    # Dropped from 0.2 m with the motors off: free fall, so the touchdown
    # is at t = sqrt(2h/g) and sqrt(2gh) m/s, above the default 1 m/s.
    drop = geopid.load_scene({
        "name": "drop", "duration": 1.0,
        "initial": {"x": [0.0, 0.0, -0.3]},
        "ground": {},
        "plan": [{"mode": "motors-off"}],
        "integrator": {"kind": "rk4", "dt": 0.001},
    })
    r = geopid.run(drop)
    term = r.termination
    assert term["kind"] == "crashed" and 0 <= term["point"] < 4
    g, h = 9.81, 0.2
    # Located to the bisection's tolerance; RK4 is exact on free fall.
    assert abs(term["t"] - math.sqrt(2 * h / g)) < 1e-9, term
    assert abs(term["speed"] - math.sqrt(2 * g * h)) < 1e-9, term
    assert r.t[-1] == term["t"]
