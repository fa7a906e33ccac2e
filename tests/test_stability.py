"""Stability suite (issue 6): the quick matrix, hypothesis properties of every law over
many orders of magnitude, and one reproducer per weakness found (a regression test now
that its kernel is fixed; a new weakness is added as a strict xfail until it is).
Tolerances are the named constants of ``rbimpact.stability``."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings, strategies as st

from rbimpact import NoSolutionError, resolve
from rbimpact import stability as S

LABELS = [lab for lab, _, _ in S.LAW_VARIANTS]


# ============================================================================================
# the quick matrix
# ============================================================================================
@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    path = tmp_path_factory.mktemp("stab") / "quick.csv"
    text, rows, ok = S.stability_report(quick=True, out=str(path))
    return text, rows, ok, path


def test_quick_report_shape(quick):
    text, rows, ok, path = quick
    lines = text.splitlines()
    assert len(lines) == len(rows) + 3                  # header, rule, rows, summary
    assert lines[-1].startswith("stability:") and f"{len(rows)} cells" in lines[-1]
    assert {r.kind for r in rows} == {"law", "stepper"}
    assert {r.dim for r in rows} == {2, 3}
    assert all(r.status in ("OK", "FAIL", "DOC-ERR", "NOT-RUN") for r in rows)
    assert ok == (not any(r.status == "FAIL" for r in rows))
    with open(path) as f:
        assert f.readline().strip().split(",")[:5] == S.FIELDS[:5]
        assert sum(1 for _ in f) == len(rows)


def test_quick_matrix_has_no_failure(quick):
    """Every cell of the quick matrix is OK or a documented error (each weakness found was
    fixed in its kernel; the reproducers are the regression tests below)."""
    _, rows, ok, _ = quick
    failed = [(r.kind, r.name, r.case, r.dim, r.note, r.repro) for r in rows
              if r.status == "FAIL"]
    assert ok and not failed, failed


def test_quick_documented_errors(quick):
    """Painleve-type 3D coupling: Routh raises its documented NoSolutionError (mode -1)."""
    _, rows, _, _ = quick
    cell = {(r.name, r.case, r.dim): r for r in rows}
    for kind in ("routh-energetic", "routh-newton"):
        r = cell[(kind, "painleve", 3)]
        assert r.status == "DOC-ERR" and "mode -1" in r.note


# ============================================================================================
# hypothesis: every law over many orders of magnitude
# ============================================================================================
@st.composite
def contacts(draw, dim, log_cond, brach=False):
    """(v, W, params): W = s Q diag(1, 10^-f c, 10^-c) Q^T with c in ``log_cond``, the scale
    s over 18 decades; v_N over 18 decades; v_T components 0 or over 308 decades; mu 0 or
    over 18 decades; e in [0, 1] (Brach [-1, 1]) with its end points; e_t in [-1, 1]."""
    c = draw(st.floats(*log_cond))
    scale = 10.0 ** draw(st.floats(-9, 9))
    if dim == 2:
        a = draw(st.floats(0, math.pi))
        Q = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        eig = np.array([1.0, 10.0 ** -c])
    else:
        q = np.array([draw(st.floats(-1, 1)) for _ in range(4)]) + np.array([1e-3, 0, 0, 0])
        w, x, y, z = q / np.linalg.norm(q)
        Q = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                      [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                      [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        eig = np.array([1.0, 10.0 ** (-c * draw(st.floats(0, 1))), 10.0 ** -c])
    W = scale * (Q * eig) @ Q.T
    W = 0.5 * (W + W.T)
    try:
        np.linalg.cholesky(W)
    except np.linalg.LinAlgError:
        W = W + np.eye(dim) * 1e-12 * np.abs(W).max()
    v = np.empty(dim)
    v[0] = -10.0 ** draw(st.floats(-10, 8))
    for k in range(1, dim):
        v[k] = draw(st.one_of(st.just(0.0), st.builds(
            lambda s, x: s * 10.0 ** x, st.sampled_from([-1.0, 1.0]), st.floats(-300, 8))))
    mu = draw(st.one_of(st.just(0.0), st.floats(-12, 6).map(lambda x: 10.0 ** x)))
    lo = -1.0 if brach else 0.0
    e = draw(st.one_of(st.sampled_from([lo, 0.0, 1.0]), st.floats(lo, 1.0)))
    e_t = draw(st.floats(-1.0, 1.0))
    return v, W, dict(e=e, mu=mu, e_t=e_t)


def _check(label, contact):
    v, W, params = contact
    ev = S.check_impact(label, v, W, params, iterations=False, timing=False)
    assert ev.status in ("OK", "DOC-ERR"), f"{ev.note}\n{S._repro(label, v, W, params)}"


_SET = dict(deadline=None, derandomize=True, database=None,
            suppress_health_check=list(HealthCheck))
_NOSHRINK = dict(_SET, phases=(Phase.explicit, Phase.generate))

#: (law variant, dim) -> reason, for the properties a kernel weakness breaks
XFAIL_MODERATE = {}
XFAIL_STIFF = {}
# (none at present.) A stiff-regime cell listed there fails or passes depending on the
# examples drawn near the boundary of the weakness (the kernels' results change bit-wise
# with compilation flags), so it is recorded as a known failure without requiring it to fail.
STIFF_STRICT = False


def _cells(xfails, strict=True):
    out = []
    for dim in (2, 3):
        for lab in LABELS:
            marks = ()
            if (lab, dim) in xfails:
                marks = pytest.mark.xfail(strict=strict, reason=xfails[(lab, dim)])
            out.append(pytest.param(lab, dim, marks=marks, id=f"{lab}-{dim}d"))
    return out


@pytest.mark.parametrize("label, dim", _cells(XFAIL_MODERATE, strict=STIFF_STRICT))
@settings(max_examples=50, **_SET)
@given(data=st.data())
def test_law_properties_moderate(label, dim, data):
    """cond(W) <= 1e3: finite outputs or a documented error, no energy gain beyond
    ENERGY_RTOL for the never-gain laws, residuals below RESID_RTOL (Routh 3D: 100 tol)."""
    _check(label, data.draw(contacts(dim, (0.0, 3.0), brach=label == "brach")))


@pytest.mark.parametrize("label, dim", _cells(XFAIL_STIFF, strict=STIFF_STRICT))
@settings(max_examples=80, **_NOSHRINK)
@given(data=st.data())
def test_law_properties_stiff(label, dim, data):
    """cond(W) from 1e8 to 1e12: the same properties."""
    _check(label, data.draw(contacts(dim, (8.0, 12.0), brach=label == "brach")))


# ============================================================================================
# reproducers of the weaknesses found (regression tests: each was fixed in its kernel)
# ============================================================================================
W_THIN_ROD = [[50000001.00000001, -50000000.0], [-50000000.0, 50000000.999999985]]


def _gain_ok(v, W, imp, rtol=S.ENERGY_RTOL):
    v, W = np.asarray(v, float), np.asarray(W, float)
    dE = S.exact_dE(v, W, imp.P)
    scale = max(S.kinetic_energy(v, W),
                0.5 * float(np.sum(np.abs(imp.P) * (np.abs(v) + np.abs(imp.v_f)))))
    return dE <= rtol * scale


def test_smith_2d_pole_crossing():
    """Regression (found by this suite, fixed in kernels/smith.py): the Halley step taken
    as converged crossed the pole of P_N(b), giving P_N = -0.61 and dE = +0.375 J."""
    imp = resolve("smith", [-1.0, 1.0], W_THIN_ROD, e=0.0, mu=5.0)
    assert imp.P[0] > 0 and _gain_ok([-1.0, 1.0], W_THIN_ROD, imp)


def test_smith_2d_root_next_to_pole():
    """Regression (fixed: next to the pole Smith 2D solves for D itself): the bracket
    collapsed onto the pole (det W = 4.6e-11) and the kernel returned NOT_CONVERGED."""
    resolve("smith", [-3.517878566115149e-09, -2.2180756715305785],
            [[0.008713034641120995, -0.0929360942974978],
             [-0.0929360942974978, 0.9912869654044664]],
            e=0.449490114439265, mu=0.4587491405715202)


def test_smith_2d_energy_near_stick():
    """Regression (fixed): g = (1 - t^2)/(1 + t^2) lost its relative accuracy near t = 1
    and D = W_NN - mu W_NT g amplified it: dE/E_scale = +4e-9 at cond(W) = 4.5e4."""
    v = [-1.1854352582423824e-09, 2.8547501250500718e-18]
    W = [[45061110.89759508, 86702017.70492016], [86702017.70492016, 166845469.18473718]]
    assert _gain_ok(v, W, resolve("smith", v, W, e=1.0, mu=1414.6136754198014))


def test_smith_3d_tiny_slip_stall():
    """Regression (fixed): no convergence for 1e-30 < |v_T|/|v_N| < ~1e-8 with large mu."""
    resolve("smith", [-1.0, 1e-10, 0.0], S.W3_SWERVE, e=0.5, mu=1000.0)


def test_smith_3d_large_mu_accuracy():
    """Regression (fixed: near stick Smith 3D converges on g, not on b): P_T was only
    accurate to ~mu 1e-14 (residual 1.06e-10 at mu = 1e6)."""
    v = np.array([-4.0, -2.0, 1.0])
    imp = resolve("smith", v, S.W3_SWERVE, e=1.0, mu=1e6)
    res, tol = S.law_residual("smith", v, S.W3_SWERVE, dict(e=1.0, mu=1e6), imp.P,
                              imp.mode_code)
    assert res <= tol


@pytest.mark.parametrize("law", ["kane_levinson", "brach", "chatterjee_ruina", "smith"])
def test_3d_spd_rejected(law):
    """Regression (fixed: common.spd3_solve; Smith by its own scaling): an SPD W of cond
    5.6e9 whose cofactor determinant came out negative is accepted."""
    W = [[5373.253418896723, 2793.1580554897914, 12198.128893487266],
         [2793.1580554897914, 1451.956825583143, 6340.907357175057],
         [12198.128893487266, 6340.907357175057, 27691.66801277434]]
    resolve(law, [-1036.9590984213548, 0.08664642602372336, 0.0], W, e=0.86, mu=5.36)


def test_routh_3d_false_jam():
    """Regression (fixed: the stick slope is common.schur3, compensated): Cramer's rule
    gave -2.9e-5 (true 3.3e-5), a false Painleve jam."""
    W = [[5373.253418896723, 2793.1580554897914, 12198.128893487266],
         [2793.1580554897914, 1451.956825583143, 6340.907357175057],
         [12198.128893487266, 6340.907357175057, 27691.66801277434]]
    resolve("routh", [-1036.9590984213548, 0.08664642602372336, 0.0], W, e=0.86, mu=5.36)


def test_routh_3d_cone():
    """Regression (fixed: P_T is integrated with the slip, dP_T/dp = -mu u): recovering
    it through W_TT^-1 put |P_T| at 667 mu P_N."""
    W = [[1.0, -0.5, 5e-4], [-0.5, 1.0, 0.0], [5e-4, 0.0, 1e-6]]
    imp = resolve("routh", [-1.0, 1e-9, 0.0], W, e=0.5, mu=1e-9)
    assert np.linalg.norm(imp.P[1:]) <= 1e-9 * imp.P[0] * (1 + 1e-6)


def test_routh_2d_energy_cond_1e12():
    """Regression (fixed: compensated slopes, Kahan FMA stick slope): the energetic law
    created energy, dE/E_scale = +1.4e-9, at cond(W) = 1e12."""
    v = [-1.0, 0.5]
    W = [[2.0135933458543687e-05, -0.004487262751694798],
         [-0.004487262751694798, 0.9999798640675412]]
    assert _gain_ok(v, W, resolve("routh", v, W, e=1.0, mu=0.3))


def test_kane_levinson_2d_stick_residual():
    """Regression (fixed: the 2D stick trial uses Kahan's FMA determinants, common.det2k):
    Cramer's rule left v_fT = 4.5e-10 s for the thin rod (cond 1e8)."""
    v = np.array([-1.0, 1.0])
    imp = resolve("kane_levinson", v, W_THIN_ROD, e=0.0, mu=5.0)
    s = np.linalg.norm(v) + np.linalg.norm(W_THIN_ROD, 2) * np.linalg.norm(imp.P)
    assert imp.mode == "stick" and abs(imp.v_f[1]) <= S.RESID_RTOL * s


def test_brach_3d_stick_cofactor_solve():
    """Regression (fixed: common.spd3_solve, compensated cofactors and one refinement
    step): the cofactor solve missed v_fT = 0 by 1.9e-7 s at cond(W) = 6.7e11."""
    v = np.array([-6583.876388369971, 0.0, 0.0])
    W = np.array([[1.5224270311101227, 2.0461907181712737, -1.985885176336621],
                  [2.0461907181712737, 2.7501458986920353, -2.6690933183829935],
                  [-1.985885176336621, -2.6690933183829935, 2.590429528825504]])
    imp = resolve("brach", v, W, e=0.0, mu=54525.22602201105, e_t=-0.25008103118059777)
    s = np.linalg.norm(v) + np.linalg.norm(W, 2) * np.linalg.norm(imp.P)
    assert np.linalg.norm(imp.v_f[1:]) <= S.RESID_RTOL * s


def test_smith_3d_energy_cond_1e12():
    """Regression (fixed during this work): v_fT = (150, -10) m/s from |v_T| = 0.56 m/s,
    dE = +0.43 K0, at cond(W) = 1e12."""
    v = np.array([-1.0, -0.5, 0.25])
    W = np.array([[1.948708134532737e-06, -0.0013749881230302153, 9.307323259674075e-05],
                  [-0.0013749881230302153, 0.9954582238545546, -0.06722539302147472],
                  [9.307323259674075e-05, -0.06722539302147472, 0.00454082743831097]])
    assert _gain_ok(v, W, resolve("smith", v, W, e=1.0, mu=5.0))


def test_smith_3d_set_valued_schur():
    """Regression (fixed: common.schur3): the Schur complement by Cramer's rule cancelled
    at cond(W) = 3.1e10, giving P_N = -983 N s."""
    v = np.array([-515.1831931990838, 1.4846866820938272e-93, 3.463512756076037e-196])
    W = np.array([[3668340.860681912, -3624150.5111939665, -6954111.172863282],
                  [-3624150.5111939665, 3580492.498268053, 6870339.078092478],
                  [-6954111.172863282, 6870339.078092478, 13182979.459354883]])
    imp = resolve("smith", v, W, e=1.0, mu=5176.209204024562)
    assert imp.P[0] > 0 and _gain_ok(v, W, imp)


def test_painleve_3d_documented_error():
    """The brief's Painleve-type 3D example: Routh (energetic) raises NoSolutionError."""
    with pytest.raises(NoSolutionError) as exc:
        resolve("routh", S.V3_PAINLEVE, S.W3_PAINLEVE, e=0.5, mu=7.5)
    assert exc.value.mode_code == -1


def test_kane_levinson_2d_painleve_solvable():
    """K&L 2D under Painleve-type coupling (mu |W_NT| >= W_NN) still has a solution."""
    W = S.W3_PAINLEVE[:2, :2]
    for vt in (1.0, -1.0, 0.0):
        imp = resolve("kane_levinson", [-0.5, vt], W, e=0.5, mu=7.5)
        assert imp.P[0] > 0


# ---- stepper --------------------------------------------------------------------------------
def _scene(case, dim):
    return next(c for c in S.stepper_cases(quick=True) if c.case == case and c.dim == dim)


def test_stepper_flat_box_sequential_2d():
    """Regression: a 0.2 x 0.1 box (routh e=0.5 mu=0.3) landing flat corner after corner
    pivots down on one corner; it ended in the documented 'impacts accumulate at a single
    contact point' before 2D had an integrated pivot contact (kernels/pivot2d.py)."""
    row = S.run_scene(_scene("box_lands_flat_sequential", 2), quick=True)
    assert row.status == "OK", row.note


@pytest.mark.parametrize("dim", [2, 3])
def test_stepper_zeno_penetration(dim):
    """Regression (fixed: during the Zeno jump the body is held on the plane): it flew
    freely to t_inf and dipped 4 h/(1-e)^2 = 3.9e-6 m below the floor at e = 0.99."""
    row = S.run_scene(_scene("zeno_e=0.99", dim), quick=True)
    assert row.residual <= row.tol, row.note


def test_stepper_break_shot_3d_energy():
    """Regression (fixed in Routh 3D's ray lock-on): the ball-wall impact at t = 1.2853 s of
    the frictional break shot (routh e=0.95 mu=0.2, mass ratio 1e6, no gravity) has a
    sphere's W_TT = 3.5 I up to rounding (W_T1T2 = 4.5e-32), where F(phi) = 0 for every slip
    angle; the lock-on took Newton's noise-over-noise ray 45 degrees off the slip and
    recorded P = (2.7466, 0.1195, 0.1175) with dE = +0.022 J instead of the stick impulse
    (2.7466, 0, -0.1705)."""
    case = next(c for c in S.stepper_cases() if c.case == "break_mass_ratio=1e6"
                and c.dim == 3 and c.name == "routh-energetic")
    row = S.run_scene(case, quick=True)
    assert row.status == "OK", row.note


@pytest.mark.parametrize("dim", [2, 3])
def test_stepper_galperin_pi(dim):
    """Mass ratio 1e6 (disk-disk, frictionless, e = 1): 3141 collisions, energy kept."""
    row = S.run_scene(_scene("billiard_mass_ratio=1e6", dim), quick=True)
    assert row.status == "OK", row.note


def test_not_run_reported():
    """A scene that cannot be built is listed as NOT-RUN, not as a failure."""
    def boom():
        raise RuntimeError("Scene3D not available")
    row = S.run_scene(S.SceneCase("x", "y", 3, boom))
    assert row.status == "NOT-RUN" and "not available" in row.note
