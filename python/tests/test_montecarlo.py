"""Monte Carlo runs: members reproducible from (seed, index) alone, each the run an
Integrator gives with its draws, percentiles within the sketch's stated 0.55% of numpy's
exact order statistics, failures listed with their exception, bad specs refused naming
their key, and a run on a two-process Dask cluster identical to the local run."""

import json
import pickle

import numpy as np
import pytest

import lgsvi
from lgsvi import montecarlo as mc

BODY = lgsvi.RigidBody([3.3, 2.5, 3.4])
OMEGA0 = [0.1, 0.0, 0.2]
SPEC = {
    "omega": mc.normal(0.01),
    "inertia": mc.truncated_normal(0.02, 0.06),
    "attitude": mc.uniform(0.05),
    "torque": mc.normal(1e-3),
}
RUN = dict(t_end=10.0, h=0.5, nodes=10, samples=21)
FIELDS = ("member", "ok", "inertia", "attitude0", "omega0", "torque", "t", "attitude", "omega", "energy")

# The sketch's bound (lgsvi_montecarlo::statistics::RELATIVE_ERROR, half a bin of 2^(1/64)):
# its quantile is the geometric middle of the bin holding the exact order statistic.
SKETCH_RELATIVE_ERROR = 2 ** (1 / 128) - 1


def run(**kw):
    args = dict(members=60, seed=11, **RUN)
    args.update(kw)
    return mc.run(BODY, np.eye(3), OMEGA0, SPEC, **args)


def same(a, b):
    return all(np.array_equal(getattr(a, f), getattr(b, f), equal_nan=True) for f in FIELDS)


def test_members_depend_on_seed_and_index_alone():
    one, two = run(threads=1), run(threads=2)
    assert same(one, two)
    for q in (1, 50, 99):
        assert np.array_equal(one.envelope.percentile(q), two.envelope.percentile(q), equal_nan=True)
    # The first 20 of a 60-member run are the members of a 20-member run.
    short = run(members=20)
    for f in FIELDS:
        assert np.array_equal(getattr(short, f), getattr(one, f)[:20])
    other_seed = run(seed=12)
    assert not np.array_equal(other_seed.omega0, one.omega0)


def test_each_member_is_an_integrators_run_of_its_draws():
    result = run(members=5)
    assert result.ok.all() and result.errors == {}
    for k in range(5):
        body = lgsvi.RigidBody(result.inertia[k], torque=result.torque[k])
        it = lgsvi.Integrator(body, 0.5, 10, attitude=result.attitude0[k], omega=result.omega0[k])
        final = it.run_until(RUN["t_end"])
        # The integrator's inertia is rebuilt from the printed tensor (its principal axes
        # recomputed): the runs agree to rounding, a few ulps of the rates.
        np.testing.assert_allclose(final.omega[-1], result.omega[k], rtol=0, atol=1e-13)
        np.testing.assert_allclose(final.attitude[-1], result.attitude[k], rtol=0, atol=1e-13)
        assert final.t[-1] == result.t[k] == RUN["t_end"]


def test_draws_follow_their_dispersions():
    result = mc.run(BODY, np.eye(3), OMEGA0, {"omega": mc.normal(0.01), "inertia": mc.uniform(0.05)},
                    members=2000, seed=3, t_end=0.5, h=0.5, nodes=4, samples=2)
    d = result.omega0 - np.array(OMEGA0)
    # 6000 normal draws: the sample standard deviation within 5 of its standard errors
    # (0.01 / sqrt(2 * 6000) = 9e-5).
    assert abs(d.std() - 0.01) < 5 * 0.01 / np.sqrt(2 * d.size)
    moments = np.array([np.diag(j) for j in result.inertia]) / np.array([3.3, 2.5, 3.4]) - 1
    assert np.abs(moments).max() <= 0.05 + 1e-15 and np.abs(moments).max() > 0.049


def test_percentiles_are_within_the_sketch_bound_of_the_exact_ones():
    result = run(members=400)
    for axis in range(3):
        final = result.omega[:, axis]
        for q in (1, 5, 25, 50, 75, 95, 99):
            exact = np.percentile(final, q, method="inverted_cdf")
            sketch = result.percentile(f"omega_{axis + 1}", q)[-1]
            assert abs(sketch - exact) <= SKETCH_RELATIVE_ERROR * abs(exact), (axis, q)
    times = result.times
    assert times[0] == 0.0 and times[-1] == RUN["t_end"] and len(times) == 21
    # The energy of a torque-free body... is not conserved here (a torque is dispersed);
    # the departure of the nominal member from itself is zero at the start.
    assert result.percentile("attitude_departure_deg", 50)[0] >= 0.0
    stats = result.final_statistics()
    np.testing.assert_allclose(stats["omega_mean"], result.omega.mean(axis=0), rtol=1e-14)
    assert stats["departure_covariance"].shape == (3, 3)


def test_failures_are_listed_not_dropped():
    """Rates dispersed by 5 rad/s leave some members beyond the Cayley chart's reach at
    this step (|h omega| of a few radians): each is listed with its exception (a
    ChartError, or a ConvergenceError where Newton fails first), the others stand."""
    result = mc.run(BODY, np.eye(3), OMEGA0, {"omega": mc.normal(5.0)}, members=40, seed=1,
                    t_end=2.0, h=0.5, nodes=6, chart="cayley")
    failed = np.flatnonzero(~result.ok)
    assert 0 < len(failed) < 40
    assert set(result.errors) == set(failed.tolist())
    kinds = {type(e) for e in result.errors.values()}
    assert lgsvi.ChartError in kinds and kinds <= {lgsvi.ChartError, lgsvi.ConvergenceError}
    assert np.isnan(result.omega[failed]).all() and np.isfinite(result.omega[result.ok]).all()
    # A failed member's draws are still reported (to replay it).
    assert np.isfinite(result.omega0[failed]).all()
    assert result.envelope.members == result.ok.sum()


@pytest.mark.parametrize(
    "spec, words",
    [
        ({"omgea": mc.normal(0.1)}, ["omgea"]),
        ({"omega": mc.normal(-0.1)}, ["omega", "sigma"]),
        ({"inertia": mc.normal(0.01)}, ["inertia"]),
        ({"inertia": mc.uniform(0.5)}, ["inertia", "triangle"]),
        ({"mass": mc.uniform(0.1)}, ["mass"]),
        ({"omega": {"distribution": "cauchy", "sigma": 1.0}}, ["cauchy"]),
        ({"omega": mc.normal(float("nan"))}, ["dispersions"]),
        ([1, 2], ["dict"]),
    ],
)
def test_bad_specs_name_their_key(spec, words):
    with pytest.raises(lgsvi.InvalidInputError) as info:
        mc.run(BODY, np.eye(3), OMEGA0, spec, members=2, **RUN)
    for word in words:
        assert word in str(info.value), str(info.value)


def test_bad_settings():
    with pytest.raises(lgsvi.InvalidInputError, match="members"):
        run(members=0)
    with pytest.raises(lgsvi.InvalidInputError, match="seed"):
        run(seed=-1)
    with pytest.raises(lgsvi.InvalidInputError, match="samples"):
        run(samples=1)
    with pytest.raises(lgsvi.InvalidInputError, match="t_end"):
        run(t_end=float("inf"))
    with pytest.raises(lgsvi.InvalidInputError, match="body in space"):
        run(members=2, position=[1.0, 0.0, 0.0])
    with pytest.raises(lgsvi.InvalidInputError, match="gyrostat"):
        run(members=2, wheel_speeds=[1.0])
    with pytest.raises(lgsvi.InvalidInputError, match="settle_when"):
        run(members=2, settle_when="wheel_1<1")
    with pytest.raises(lgsvi.InvalidInputError, match="torque"):
        mc.run(WHEELS, np.eye(3), OMEGA0, {"torque": mc.normal(0.1)}, members=2, **RUN)
    with pytest.raises(lgsvi.InvalidInputError, match="mass"):
        mc.run(BODY, np.eye(3), OMEGA0, {"mass": mc.uniform(0.1)}, members=2, **RUN)
    with pytest.raises(lgsvi.InvalidInputError, match="channel"):
        run(members=2).percentile("omega_4", 50)
    with pytest.raises(lgsvi.LgsviError):
        run(members=2, h=-1.0)


def test_envelopes_pickle_and_merge_only_their_own_kind():
    a, b = run(members=10), run(members=10, samples=11)
    back = pickle.loads(pickle.dumps(a.envelope))
    assert np.array_equal(back.percentile(50), a.envelope.percentile(50), equal_nan=True)
    with pytest.raises(lgsvi.InvalidInputError, match="different runs"):
        back.merge(b.envelope)
    with pytest.raises(lgsvi.InvalidInputError, match="envelope"):
        lgsvi._lgsvi._montecarlo_envelope_from_bytes(b'{"channels": ["x"], "samples": 2, "sketches": []}')


def test_heavy_top_members():
    top = lgsvi.HeavyTop([1.0, 1.0, 0.4], mass=1.0, gravity=9.81, com=[0.0, 0.0, 0.3])
    result = mc.run(top, lgsvi.lie.so3_exp([0.3, 0.0, 0.0]), [0.0, 0.0, 10.0],
                    {"attitude": mc.normal(0.01)}, members=8, seed=2, t_end=1.0, h=0.05, nodes=8)
    assert result.ok.all()
    # The top's energy is conserved: its change stays at the integrator's error.
    assert np.nanmax(np.abs(result.envelope.percentile(100)[4])) < 1e-10


def test_a_dask_cluster_gives_the_local_run():
    distributed = pytest.importorskip("dask.distributed")
    spec = dict(SPEC, omega=mc.normal(5.0))  # some members fail on the Cayley chart
    args = dict(members=90, seed=5, chart="cayley", **RUN)
    local = mc.run(BODY, np.eye(3), OMEGA0, spec, **args)
    assert 0 < len(local.errors) < 90
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            remote = mc.run(BODY, np.eye(3), OMEGA0, spec, client=client, chunk_size=17, **args)
            # A sampled controller goes to the workers pickled, and runs there as here.
            law = lgsvi.control.PdLaw(1.5, 3.0, target=lgsvi.lie.so3_exp([0.5, 0.0, 0.0]),
                                      torque_limit=0.3)
            controlled = dict(members=20, seed=7, controller=law, sample_period=1.0, **RUN)
            remote_controlled = mc.run(BODY, np.eye(3), OMEGA0, {"attitude": mc.normal(0.05)},
                                       client=client, chunk_size=7, **controlled)
    local_controlled = mc.run(BODY, np.eye(3), OMEGA0, {"attitude": mc.normal(0.05)},
                              **controlled)
    assert same(local_controlled, remote_controlled) and local_controlled.ok.all()
    assert same(local, remote)
    assert set(local.errors) == set(remote.errors)
    assert all(type(local.errors[k]) is type(remote.errors[k]) for k in local.errors)
    for q in (0, 1, 50, 99, 100):
        assert np.array_equal(local.envelope.percentile(q), remote.envelope.percentile(q), equal_nan=True)


def test_members_are_the_command_lines_rows(tmp_path):
    """`lgsvi montecarlo` with the same flags draws the same members and lands on the
    same final states, bit for bit (the binary is built by the workspace's tests)."""
    import csv
    import pathlib
    import subprocess

    binary = pathlib.Path(__file__).resolve().parents[2] / "target" / "release" / "lgsvi"
    if not binary.exists():
        pytest.skip("build the command line first: cargo build --release -p lgsvi-cli")
    out = tmp_path / "run"
    subprocess.run(
        [str(binary), "montecarlo", "--inertia", "3.3,2.5,3.4", "--omega0", "0.1,0,0.2",
         "--h", "0.5", "--nodes", "10", "--t-end", "10", "--members", "6", "--seed", "11",
         "--disperse-omega", "0.01", "--disperse-inertia", "0.02", "--disperse-attitude", "1",
         "--out", str(out), "--quiet"],
        check=True,
    )
    spec = {"omega": mc.normal(0.01), "inertia": mc.truncated_normal(0.02, 0.06),
            "attitude": mc.normal(np.radians(1.0))}
    result = mc.run(BODY, np.eye(3), OMEGA0, spec, members=6, seed=11, t_end=10.0, h=0.5, nodes=10)
    with open(out / "members.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6
    for k, row in enumerate(rows):
        def got(name, n):
            return np.array([float(row[f"{name}_{i}"]) for i in n])
        three, nine = (1, 2, 3), [f"{i}{j}" for i in (1, 2, 3) for j in (1, 2, 3)]
        assert np.array_equal(got("omega0", three), result.omega0[k])
        assert np.array_equal(got("J", nine), result.inertia[k].ravel())
        assert np.array_equal(got("R0", nine), result.attitude0[k].ravel())
        assert np.array_equal(got("omega", three), result.omega[k])
        assert np.array_equal(got("R", nine), result.attitude[k].ravel())


def test_stop_times_match_the_command_line_and_are_summarised(tmp_path):
    """`stop_when` stops each member as `lgsvi montecarlo --stop-when` does: the same stop
    times, bit for bit; an axisymmetric body's Omega_1 falls through 0 near pi/(2 lambda)."""
    import csv
    import pathlib
    import subprocess

    body = lgsvi.RigidBody([1.0, 1.0, 1.8])
    spec = {"omega": mc.normal(0.05)}
    result = mc.run(body, np.eye(3), [0.3, 0.0, 1.5], spec, members=12, seed=4, t_end=10.0,
                    h=0.25, nodes=12, stop_when="omega_1<0")
    assert np.isfinite(result.t_stop).all()
    lam = 0.8 * 1.5
    assert np.all(np.abs(result.t_stop - np.pi / (2 * lam)) < 0.6)
    # Each member ends at the end of the step that holds its stop.
    assert np.all((result.t >= result.t_stop) & (result.t - result.t_stop < 0.25))
    stats = result.stop_statistics()
    assert stats["stopped"] == 12 and stats["not_stopped"] == 0
    assert stats["p50"] == np.sort(result.t_stop)[5]  # the ceil(0.5 * 12) = 6th smallest
    binary = pathlib.Path(__file__).resolve().parents[2] / "target" / "release" / "lgsvi"
    if not binary.exists():
        pytest.skip("build the command line first: cargo build --release -p lgsvi-cli")
    out = tmp_path / "run"
    subprocess.run(
        [str(binary), "montecarlo", "--inertia", "1,1,1.8", "--omega0", "0.3,0,1.5", "--h", "0.25",
         "--nodes", "12", "--t-end", "10", "--members", "12", "--seed", "4",
         "--disperse-omega", "0.05", "--stop-when", "omega_1<0", "--out", str(out), "--quiet"],
        check=True,
    )
    with open(out / "members.csv") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["t_stop"]) for r in rows] == list(result.t_stop)


def test_a_stop_condition_the_body_lacks_is_refused():
    with pytest.raises(lgsvi.InvalidInputError, match="body in space"):
        run(members=2, stop_when="x_1<0")
    with pytest.raises(lgsvi.InvalidInputError, match="QUANTITY"):
        run(members=2, stop_when="omega_1=0")


#: The command line's default gyrostat: J = diag(10, 12, 8) with three wheels of axial
#: inertia 0.05 on the body axes.
WHEELS = lgsvi.Gyrostat(np.diag([10.0, 12.0, 8.0]), np.eye(3), [0.05, 0.05, 0.05])


def _binary():
    import pathlib

    binary = pathlib.Path(__file__).resolve().parents[2] / "target" / "release" / "lgsvi"
    if not binary.exists():
        pytest.skip("build the command line first: cargo build --release -p lgsvi-cli")
    return binary


def _rows(tmp_path, args, spec=None):
    """`lgsvi montecarlo args` (and the dispersion dict `spec` as its config's
    `[montecarlo.dispersions]` table) in `tmp_path`: members.csv's rows."""
    import csv
    import subprocess

    binary = _binary()
    if spec is not None:
        config = tmp_path / "spec.toml"
        lines = ["[montecarlo.dispersions]"] + [
            f"{key} = {{ "
            + ", ".join(f"{k} = {json.dumps(v)}" for k, v in value.items())
            + " }"
            for key, value in spec.items()
        ]
        config.write_text("\n".join(lines) + "\n")
        args = [*args, "--config", str(config)]
    out = tmp_path / "run"
    subprocess.run([str(binary), "montecarlo", *args, "--out", str(out), "--quiet"], check=True)
    with open(out / "members.csv") as f:
        return list(csv.DictReader(f))


def _column(rows, name):
    return np.array([float(r[name]) if r[name] else np.nan for r in rows])


def test_gyrostat_members_are_the_command_lines_rows(tmp_path):
    """A gyrostat's members (wheel inertias and axes dispersed, wheel 1's motor spinning it
    up to a speed limit) are `lgsvi montecarlo --system gyrostat`'s rows, bit for bit:
    the draws, the final rates of body and wheels, the stop times."""
    spec = {"omega": mc.normal(0.01), "wheel_inertia": mc.uniform(0.05),
            "wheel_axis": mc.normal(0.01)}
    result = mc.run(WHEELS, np.eye(3), [0.05, 0.0, 0.0], spec, members=6, seed=5, t_end=20.0,
                    h=0.5, nodes=10, wheel_speeds=[1.0, 2.0, 3.0],
                    input=[0.0, 0.0, 0.0, 0.002, 0.0, 0.0], stop_when="wheel_1>1.5")
    assert result.ok.all() and result.wheel_speeds.shape == (6, 3)
    assert "wheel_3" in result.channels
    # Wheel 1 spins up at 0.002 / I_1 (the body barely turns): it crosses 1.5 rad/s near
    # t = 0.5 I_1 / 0.002 = 12.5 for I_1 = 0.05.
    assert np.all(np.abs(result.t_stop - 0.5 * result.wheel_inertia[:, 0] / 0.002) < 0.5)
    rows = _rows(tmp_path, [
        "--system", "gyrostat", "--omega0", "0.05,0,0", "--wheel-speeds0", "1,2,3",
        "--wheel-torque", "0.002,0,0", "--h", "0.5", "--nodes", "10", "--t-end", "20",
        "--members", "6", "--seed", "5", "--stop-when", "wheel_1>1.5",
    ], spec)
    for k in (1, 2, 3):
        assert np.array_equal(_column(rows, f"I_w{k}"), result.wheel_inertia[:, k - 1])
        assert np.array_equal(_column(rows, f"wheel_{k}"), result.wheel_speeds[:, k - 1])
        for i in (1, 2, 3):
            assert np.array_equal(_column(rows, f"a_w{k}_{i}"), result.wheel_axes[:, k - 1, i - 1])
        assert np.array_equal(_column(rows, f"omega_{k}"), result.omega[:, k - 1])
    assert np.array_equal(_column(rows, "t_stop"), result.t_stop)


def test_bodies_in_space_draw_their_mass_as_the_command_line_does(tmp_path):
    """An orbiting body's members (mass and torque dispersed) end where `lgsvi montecarlo
    --system orbiting-body`'s rows do, position and velocity included, bit for bit."""
    body = lgsvi.OrbitingBody([0.3, 0.2, 0.4], mass=1.0, mu=1.0)
    spec = {"omega": mc.normal(0.01), "mass": mc.uniform(0.1), "torque": mc.normal(0.01)}
    result = mc.run(body, np.eye(3), [0.1, 0.0, 0.2], spec, members=5, seed=2, t_end=5.0,
                    h=0.5, nodes=10, position=[3.0, 0.0, 0.0], velocity=[0.0, 0.55, 0.05])
    assert result.ok.all() and result.position.shape == (5, 3)
    assert np.all(np.abs(result.mass - 1.0) <= 0.1) and len(set(result.mass)) == 5
    rows = _rows(tmp_path, [
        "--system", "orbiting-body", "--inertia", "0.3,0.2,0.4", "--omega0", "0.1,0,0.2",
        "--position0", "3,0,0", "--velocity0", "0,0.55,0.05", "--h", "0.5", "--nodes", "10",
        "--t-end", "5", "--members", "5", "--seed", "2",
    ], spec)
    assert np.array_equal(_column(rows, "m"), result.mass)
    for i in (1, 2, 3):
        assert np.array_equal(_column(rows, f"tau_{i}"), result.torque[:, i - 1])
        assert np.array_equal(_column(rows, f"x_{i}"), result.position[:, i - 1])
        assert np.array_equal(_column(rows, f"v_{i}"), result.velocity[:, i - 1])


def test_settling_times_are_the_command_lines_and_a_damped_sphere_s_closed_form(tmp_path):
    """`settle_when`: a damped sphere's |Omega| = |Omega_0| e^(-c t / j) stays below 0.05
    from t = (j / c) ln(|Omega_0| / 0.05) on; every member's settling time within 1e-12
    relative of it, and equal to `lgsvi montecarlo --settle-when`'s, bit for bit."""
    sphere = lgsvi.RigidBody([2.0, 2.0, 2.0], damping=0.5)
    result = mc.run(sphere, np.eye(3), [0.3, 0.1, 1.0], {"omega": mc.normal(0.05)}, members=8,
                    seed=3, t_end=20.0, h=0.25, nodes=12, settle_when="omega<0.05")
    exact = 4.0 * np.log(np.linalg.norm(result.omega0, axis=1) / 0.05)
    assert np.all(np.abs(result.t_settle - exact) <= 1e-12 * exact)
    stats = result.settle_statistics()
    assert stats["settled"] == 8 and stats["not_settled"] == 0
    assert stats["min"] == result.t_settle.min()
    rows = _rows(tmp_path, [
        "--inertia", "2,2,2", "--damping", "0.5", "--omega0", "0.3,0.1,1", "--h", "0.25",
        "--nodes", "12", "--t-end", "20", "--members", "8", "--seed", "3",
        "--disperse-omega", "0.05", "--settle-when", "omega<0.05",
    ])
    assert np.array_equal(_column(rows, "t_settle"), result.t_settle)


def test_a_pd_attitude_law_settles_each_member_as_its_closed_form_says():
    """`attitude_gain` with `damping`: the PD law −Kθ − cΩ toward `target`. A sphere
    (J = 2I) at rest, turned from the target by its drawn start attitude R0 = T exp(δ),
    turns back about δ's fixed axis: 2θ'' + 4θ' + 2θ = 0 (critically damped),
    θ(t) = |δ| (1 + t) e^(−t), so its pointing error falls through 1° where
    |δ| (1 + t) e^(−t) = π/180; each member's settling time within 1e-12 relative of it
    (the run resolves θ to ~1e-14 at h = 0.25, n = 12; the crossing is located to 1e-12)."""
    from scipy.spatial.transform import Rotation

    target = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    sphere = lgsvi.RigidBody([2.0, 2.0, 2.0], damping=4.0, attitude_gain=2.0, target=target)
    again = pickle.loads(pickle.dumps(sphere))
    assert again == sphere and "attitude_gain=2" in repr(sphere)
    result = mc.run(sphere, target, [0.0, 0.0, 0.0], {"attitude": mc.normal(0.4)}, members=8,
                    seed=5, t_end=15.0, h=0.25, nodes=12, settle_when="error<1")
    turned = Rotation.from_matrix(np.einsum("ji,mjk->mik", target, result.attitude0)).magnitude()
    assert np.all(turned > 2 * np.pi / 180)
    lo, hi = np.zeros(8), np.full(8, 15.0)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        above = turned * (1 + mid) * np.exp(-mid) > np.pi / 180
        lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
    exact = 0.5 * (lo + hi)
    assert np.all(np.abs(result.t_settle - exact) <= 1e-12 * exact), result.t_settle - exact
    with pytest.raises(lgsvi.InvalidInputError, match="attitude_gain"):
        lgsvi.RigidBody([2.0, 2.0, 2.0], attitude_gain=-1.0)


def test_a_sampled_saturated_controller_turns_each_member_as_the_held_torques_closed_form():
    """`controller=PdLaw(K, C, target, torque_limit=L)` sampled every `sample_period` T and
    held. A sphere (J = 2I) at rest, turned from the target by its drawn start attitude
    R0 = T exp(δ), turns back about δ's fixed axis under a torque held between samples:
    2θ'' = u, so θ ← θ + Tω + T²u/4, ω ← ω + Tu/2 with u = −clip(Kθ + Cω, ±L), sample
    by sample. Each member's last state meets that closed form to rounding (the step is
    exact for this motion up to rounding at h = 0.25, n = 10), the limit holding its
    first samples."""
    from scipy.spatial.transform import Rotation

    target = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    law = lgsvi.control.PdLaw(2.0, 4.0, target=target, torque_limit=0.5)
    assert pickle.loads(pickle.dumps(law)) == law
    assert "torque_limit=0.5" in repr(law) and law.torque_limit == 0.5
    sphere = lgsvi.RigidBody([2.0, 2.0, 2.0])
    result = mc.run(sphere, target, [0.0, 0.0, 0.0], {"attitude": mc.normal(0.4)}, members=8,
                    seed=5, t_end=15.0, h=0.25, nodes=10, controller=law, sample_period=0.5,
                    settle_when="error<1")
    assert np.all(result.ok)
    delta = Rotation.from_matrix(np.einsum("ji,mjk->mik", target, result.attitude0)).as_rotvec()
    theta = np.linalg.norm(delta, axis=1)
    axis = delta / theta[:, None]
    omega = np.zeros(8)
    saturated = 0
    for _ in range(30):
        demand = 2.0 * theta + 4.0 * omega
        saturated += np.count_nonzero(np.abs(demand) > 0.5)
        u = -np.clip(demand, -0.5, 0.5)
        theta, omega = theta + 0.5 * omega + 0.25 * u / 4.0, omega + 0.5 * u / 2.0
    assert saturated >= 8
    final = Rotation.from_matrix(np.einsum("ji,mjk->mik", target, result.attitude)).as_rotvec()
    assert np.max(np.abs(final - axis * theta[:, None])) < 1e-13
    assert np.max(np.abs(result.omega - axis * omega[:, None])) < 1e-13
    # The pointing error is measured from the controller's target: every member settles.
    assert "error_deg" in result.channels and np.all(np.isfinite(result.t_settle))


def test_a_pd_law_gives_the_input_of_its_states_group():
    """`PdLaw.input(state)`: −Kθ − CΩ (θ the rotation vector from the target, by scipy),
    scaled back to the torque limit where longer; three entries on SO(3), the torque and
    a zero force on SE(3)."""
    from scipy.spatial.transform import Rotation

    target = Rotation.from_rotvec([0.3, -0.5, 0.8]).as_matrix()
    attitude = Rotation.from_rotvec([-0.2, 0.4, 0.1]).as_matrix()
    omega = np.array([0.1, -0.3, 0.2])
    theta = Rotation.from_matrix(target.T @ attitude).as_rotvec()
    demand = -1.5 * theta - 2.0 * omega
    # scipy's rotation vector and lgsvi's log agree to a few ulps of these order-one values.
    state = lgsvi.Integrator(lgsvi.RigidBody([2.0, 3.0, 4.0]), attitude=attitude,
                             omega=omega, h=0.5, nodes=8).state
    free = lgsvi.control.PdLaw(1.5, 2.0, target=target)
    assert free.torque_limit is None
    assert np.allclose(free.input(state), demand, rtol=0, atol=1e-14)
    assert abs(free.error(state) - np.linalg.norm(theta)) < 1e-14
    limit = 0.5 * np.linalg.norm(demand)
    limited = lgsvi.control.PdLaw(1.5, 2.0, target=target, torque_limit=limit)
    assert np.allclose(limited.input(state), 0.5 * demand, rtol=0, atol=1e-14)
    moving = lgsvi.Integrator(lgsvi.FreeBody([2.0, 3.0, 4.0], mass=2.0), attitude=attitude,
                              omega=omega, h=0.5, nodes=8).state
    u = free.input(moving)
    assert u.shape == (6,) and np.allclose(u[:3], demand, rtol=0, atol=1e-14)
    assert np.all(u[3:] == 0.0)


def test_bad_controllers_are_refused_naming_what_to_change():
    law = lgsvi.control.PdLaw(1.0, 1.0)
    run = dict(members=2, t_end=2.0, h=0.5, nodes=8)
    for kwargs, words in [
        (dict(controller=law), "sample_period"),
        (dict(sample_period=0.5), "controller"),
        (dict(controller=law, sample_period=0.3), "whole number of steps"),
        (dict(controller=law, sample_period=-1.0), "positive"),
        (dict(controller=law, sample_period=0.5, input=[0.1, 0.0, 0.0]), "one of them"),
    ]:
        with pytest.raises(lgsvi.InvalidInputError, match=words):
            mc.run(BODY, np.eye(3), OMEGA0, **run, **kwargs)
    with pytest.raises(lgsvi.InvalidInputError, match="wheels"):
        mc.run(WHEELS, np.eye(3), OMEGA0, **run, controller=law,
               sample_period=0.5)
    with pytest.raises(lgsvi.InvalidInputError, match="attitude law of its own"):
        mc.run(lgsvi.RigidBody([2.0, 3.0, 4.0], attitude_gain=1.0), np.eye(3), OMEGA0, **run,
               controller=law, sample_period=0.5)
    with pytest.raises(lgsvi.InvalidInputError, match="setting h = -0.5"):
        mc.run(BODY, np.eye(3), OMEGA0, members=2, t_end=2.0, h=-0.5, nodes=8,
               controller=law, sample_period=0.5)
    for args, words in [((-1.0,), "gain"), ((1.0, float("nan")), "rate_gain")]:
        with pytest.raises(lgsvi.InvalidInputError, match=words):
            lgsvi.control.PdLaw(*args)
    with pytest.raises(lgsvi.InvalidInputError, match="torque_limit"):
        lgsvi.control.PdLaw(1.0, torque_limit=0.0)


def test_sampled_controller_members_are_the_command_lines_rows(tmp_path):
    """`controller=PdLaw(...)`, `sample_period` run each member as `lgsvi montecarlo
    --sample-period --torque-limit` does: the same settling times and final rates, bit
    for bit."""
    target = lgsvi.lie.matrix_from_quaternion([0.8, 0.6, 0.0, 0.0])
    spec = {"omega": mc.normal(0.05), "attitude": mc.normal(np.radians(5.0))}
    rows = _rows(tmp_path, [
        "--inertia", "2,3,4", "--omega0", "0,0,0", "--attitude-gain", "1.5", "--damping", "3",
        "--target-quaternion", "0.8,0.6,0,0", "--sample-period", "0.5", "--torque-limit", "0.3",
        "--h", "0.25", "--nodes", "10", "--t-end", "25", "--members", "6", "--seed", "4",
        "--settle-when", "error<0.5",
    ], spec)
    law = lgsvi.control.PdLaw(1.5, 3.0, target=target, torque_limit=0.3)
    result = mc.run(lgsvi.RigidBody([2.0, 3.0, 4.0]), np.eye(3), [0.0, 0.0, 0.0], spec,
                    members=6, seed=4, t_end=25.0, h=0.25, nodes=10, controller=law,
                    sample_period=0.5, settle_when="error<0.5")
    assert np.all(np.isfinite(result.t_settle))
    assert np.array_equal(_column(rows, "t_settle"), result.t_settle)
    for i in (1, 2, 3):
        assert np.array_equal(_column(rows, f"omega_{i}"), result.omega[:, i - 1])
