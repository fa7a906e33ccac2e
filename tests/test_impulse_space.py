"""Impulse space of one contact (issue 8): ellipse, cone, P_I, P_II, what each law reaches,
where energy is created, the 3D plane of interest and the plot. DESIGN §5 case 1b throughout."""
import subprocess
import sys

import numpy as np
import pytest

import rbimpact
from rbimpact import Law
from rbimpact.impulse_region import (ImpulseSpace, energy_change, impulse_space,
                                    impulse_space_report)

ROD = np.array([[2.5, -1.5], [-1.5, 2.5]])
V1B = np.array([-1.0, 1.0])
MU = 0.3
ROUND = 1e-12
ALL_KEYS = ["kane_levinson", "smith", "routh", "routh:poisson", "routh:newton", "brach",
            "chatterjee_ruina"]


@pytest.fixture(scope="module")
def case1b():
    return impulse_space(V1B, ROD, MU)


@pytest.fixture(scope="module")
def case1b_frictionless():
    return impulse_space(V1B, ROD, 0.0, n=50, n_grid=11)


def test_result_object_and_lazy_name(case1b):
    assert isinstance(case1b, ImpulseSpace)
    assert isinstance(rbimpact.impulse_space(V1B, ROD, MU, laws=("smith",), n=8),
                      ImpulseSpace)
    assert list(case1b.reach) == ALL_KEYS
    assert case1b.reach["routh"].fixed["restitution"] == "energetic"
    for r in case1b.reach.values():
        m = r.P.shape[0]
        assert m > 0 and r.P.shape == (m, 2) and r.P_full.shape == (m, 2)
        for a in (r.P, r.P_full, r.v_f, r.dE):
            assert np.isfinite(a).all()
        assert r.energy_gain.dtype == bool and r.energy_gain.shape == (m,)
        assert (r.mode >= 0).all()
        # dE reported = exact P.(v + v_f)/2
        np.testing.assert_allclose(r.dE, energy_change(r.P_full, V1B, ROD), atol=1e-14)
    assert case1b["kane_levinson"].kind == "curve" and case1b["brach"].kind == "region"
    assert case1b["kane_levinson"].P.shape[0] == 200
    assert case1b["chatterjee_ruina"].P.shape[0] == 41 * 41


def test_P_I_P_II_and_energy_ellipse(case1b):
    s = case1b
    np.testing.assert_allclose(s.P_I, [0.4, 0.0], atol=1e-15)
    np.testing.assert_allclose(s.P_II, [0.25, -0.25], atol=1e-15)
    # P_II is the minimum of dE: gradient v + W P_II = 0, value -v.W^-1 v / 2
    np.testing.assert_allclose(V1B + ROD @ s.P_II, 0.0, atol=1e-15)
    assert s.dE_min == pytest.approx(-0.25, abs=1e-15)
    rng = np.random.default_rng(1)
    P = s.P_II + rng.normal(scale=0.5, size=(2000, 2))
    assert (energy_change(P, V1B, ROD) >= s.dE_min).all()
    # boundary dE = 0 through 0 and 2 P_II
    assert s.ellipse.shape == (200, 2)
    assert np.abs(s.dE(s.ellipse_full)).max() < ROUND
    assert np.abs(energy_change(s.ellipse, V1B, ROD)).max() < ROUND
    assert s.dE(2 * s.P_II_full) == pytest.approx(0.0, abs=ROUND)
    np.testing.assert_array_equal(s.ellipse[0], [0.0, 0.0])
    np.testing.assert_allclose(s.ellipse[100], 2 * s.P_II, atol=1e-15)
    # the samples go round the ellipse once: angles about P_II are monotone
    ang = np.unwrap(np.arctan2(*(s.ellipse - s.P_II).T[::-1]))
    d = np.diff(ang)
    assert (np.sign(d) == np.sign(d[0])).all()
    assert abs(ang[-1] - ang[0] + d[0]) == pytest.approx(2 * np.pi, rel=1e-12)


def test_friction_cone_and_extent(case1b):
    s = case1b
    (nlo, nhi), (tlo, thi) = s.extent
    up, apex, lo = s.cone
    np.testing.assert_array_equal(apex, [0.0, 0.0])
    assert up[1] == pytest.approx(MU * up[0]) and lo[1] == pytest.approx(-MU * lo[0])
    for P in (up, lo):
        assert nlo <= P[0] <= nhi + 1e-15 and tlo - 1e-15 <= P[1] <= thi + 1e-15
    # the ray is clipped where it leaves the extent, not before
    assert up[0] == pytest.approx(nhi) or up[1] == pytest.approx(thi)
    pts = np.concatenate([s.ellipse] + [r.P for r in s.reach.values()])
    assert (pts[:, 0] > nlo).all() and (pts[:, 0] < nhi).all()
    assert (pts[:, 1] > tlo).all() and (pts[:, 1] < thi).all()


def test_case_1b_who_creates_energy(case1b):
    """Kane & Levinson's curve leaves the ellipse; Smith, Routh (energetic, Poisson) and
    Chatterjee-Ruina stay inside it (dE <= 0 up to round-off)."""
    kl = case1b["kane_levinson"]
    assert kl.energy_gain.any()
    assert kl.dE.max() == pytest.approx(0.0625, abs=1e-9)
    # the gain is at high e (sticking with coupling), not at e = 0
    assert kl.energy_gain[-1] and not kl.energy_gain[0]
    assert kl.params["e"][kl.energy_gain].min() > 0.5
    for key in ("smith", "routh", "routh:poisson", "chatterjee_ruina"):
        r = case1b[key]
        assert not r.energy_gain.any(), key
        assert r.dE.max() <= ROUND, (key, r.dE.max())
    # Brach contains Kane & Levinson's curve (e_t = 0, 2D) and so creates energy too
    br = case1b["brach"]
    assert br.energy_gain.any()
    assert (br.params["e"][br.energy_gain] > 0).all()
    # the flag agrees with the sign of dE away from round-off
    for r in case1b.reach.values():
        assert (r.dE[r.energy_gain] > 0).all(), r.key
        assert r.energy_gain[r.dE > 1e-9].all(), r.key


def test_case_1b_reference_points_at_e_1(case1b):
    s = case1b
    kl = s["kane_levinson"]
    i = kl.at(1.0)
    assert kl.params["e"][i] == 1.0
    np.testing.assert_allclose(kl.P[i], [0.875, 0.125], atol=1e-9)
    np.testing.assert_allclose(kl.v_f[i], [1.0, 0.0], atol=1e-9)
    assert kl.dE[i] == pytest.approx(0.0625, abs=1e-9)
    assert kl.mode_names[i] == "stick"                        # K&L sticks at e = 1 (DESIGN)
    expected_vf = {"routh": [0.851143, -0.197573], "routh:poisson": [0.789831, -0.175141],
                   "smith": [1.0, -0.433678], "chatterjee_ruina": [1.0, -0.525424],
                   "brach": [1.0, 0.0]}
    for key, vf in expected_vf.items():
        r = s[key]
        i = r.at(1.0, 0.0)
        assert r.params["e"][i] == 1.0
        np.testing.assert_allclose(r.v_f[i], vf, atol=2e-6, err_msg=key)
        # the point is the impulse that produces that v_f
        np.testing.assert_allclose(r.P[i], np.linalg.solve(ROD, np.array(vf) - V1B), atol=5e-6)
    assert s["routh"].dE[s["routh"].at(1.0)] == pytest.approx(-0.074474, abs=2e-6)


def test_curves_follow_e(case1b):
    """Along each curve e runs over [0, 1]; the Newton-type laws keep v_fN = -e v_N, and
    at e = 0 every curve law ends at v_fN = 0 (plastic)."""
    for key in ("kane_levinson", "smith", "routh", "routh:poisson", "routh:newton"):
        r = case1b[key]
        np.testing.assert_array_equal(r.params["e"], np.linspace(0, 1, 200))
        assert r.v_f[0, 0] == pytest.approx(0.0, abs=1e-9), key
    for key in ("kane_levinson", "smith", "routh:newton", "brach", "chatterjee_ruina"):
        r = case1b[key]
        np.testing.assert_allclose(r.v_f[:, 0], -r.params["e"] * V1B[0], atol=1e-9,
                                   err_msg=key)
    # every reached impulse is in the friction cone and pushes (P_N >= 0)
    for r in case1b.reach.values():
        assert (r.P[:, 0] >= -1e-15).all()
        assert (np.abs(r.P[:, 1]) <= MU * r.P[:, 0] + 1e-12).all(), r.key


def test_region_outline_bounds_the_grid(case1b):
    from matplotlib.path import Path
    for key in ("brach", "chatterjee_ruina"):
        r = case1b[key]
        assert r.outline.shape[1] == 2 and r.outline.shape[0] > 10
        np.testing.assert_array_equal(r.outline[0], r.outline[-1])
        inside = Path(r.outline).contains_points(r.P, radius=1e-9) | Path(
            r.outline).contains_points(r.P, radius=-1e-9)
        assert inside.all(), (key, r.P[~inside][:5])
        # the outline is made of reachable impulses: inside the cone
        assert (np.abs(r.outline[:, 1]) <= MU * r.outline[:, 0] + 1e-12).all()
    cr = case1b["chatterjee_ruina"]
    # C&R region: from P_I (e = 0, e_t = -1) to 2 P_I (e = 1, e_t = -1)
    np.testing.assert_allclose(cr.P[cr.at(0.0, -1.0)], case1b.P_I, atol=1e-12)
    np.testing.assert_allclose(cr.P[cr.at(1.0, -1.0)], 2 * case1b.P_I, atol=1e-12)


def test_frictionless_elastic_point_is_on_the_ellipse(case1b_frictionless):
    s = case1b_frictionless
    assert list(s.reach) == ALL_KEYS
    for r in s.reach.values():
        at1 = r.params["e"] == 1.0
        assert at1.any(), r.key
        assert np.abs(r.dE[at1]).max() <= ROUND, (r.key, r.dE[at1])
        assert not r.energy_gain.any(), r.key
        np.testing.assert_allclose(r.P[at1], np.broadcast_to(2 * s.P_I, r.P[at1].shape),
                                   atol=1e-12, err_msg=r.key)
        assert np.abs(r.P[:, 1]).max() <= 1e-15


@pytest.mark.parametrize("seed", range(4))
def test_random_contacts_frictionless_e1_on_ellipse(seed):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(2, 2))
    W = A @ A.T + 0.2 * np.eye(2)
    v = np.array([-rng.uniform(0.2, 3.0), rng.normal()])
    s = impulse_space(v, W, 0.0, laws=("kane_levinson", "smith", "routh", "chatterjee_ruina"),
                      n=16, n_grid=3, routh_restitution=("energetic", "poisson"))
    assert np.abs(s.dE(s.ellipse_full)).max() < 1e-12 * max(1.0, -s.dE_min)
    for r in s.reach.values():
        i = r.at(1.0, 0.0)
        assert r.dE[i] == pytest.approx(0.0, abs=1e-12 * max(1.0, -s.dE_min)), r.key


def test_failed_points_are_left_out_and_flagged(monkeypatch):
    """Parameters with no solution are kept out of the arrays (never NaN) and listed."""
    orig = Law.resolve_batch

    def flaky(self, v, W, **kw):
        res = orig(self, v, W, **kw)
        bad = kw["e"] > 0.75 if np.ndim(kw["e"]) else np.zeros(len(v), bool)
        res.mode[bad] = -1
        res.P[bad] = 0.0
        res.v_f[bad] = v[bad]
        res.dE[bad] = 0.0
        return res

    monkeypatch.setattr(Law, "resolve_batch", flaky)
    s = impulse_space(V1B, ROD, MU, laws=("kane_levinson", "chatterjee_ruina"), n=40, n_grid=5)
    kl, cr = s["kane_levinson"], s["chatterjee_ruina"]
    assert kl.n_failed == 10 and kl.P.shape == (30, 2)
    assert (kl.params["e"] <= 0.75).all() and (kl.failed["e"] > 0.75).all()
    assert (kl.failed["mode"] == -1).all()
    assert not kl.energy_gain.any()           # the gaining part (e > 0.89) failed
    assert cr.n_failed == 5 and cr.P.shape == (20, 2) and cr.failed["e_t"].shape == (5,)
    assert (cr.outline[:, 0] <= 1.75 * s.P_I[0] + 1e-12).all()
    for r in s.reach.values():
        for a in (r.P, r.P_full, r.v_f, r.dE, r.outline if r.outline is not None else r.P):
            assert np.isfinite(a).all()
    text = s.summary()
    assert "no solution at 10 samples" in text and "(no solution)" in text


def test_3d_plane_of_interest():
    """A 3D contact is drawn in the plane of n and the initial slip: an isotropic sphere
    slipping along (0.6, 0.8) gives exactly the 2D picture of v = (-1, 1)."""
    W3 = np.diag([1.0, 3.5, 3.5])
    v3 = np.array([-1.0, 0.6, 0.8])
    laws = ("kane_levinson", "routh", "chatterjee_ruina")
    kw = dict(laws=laws, n=21, n_grid=5, routh_restitution=("energetic",))
    s3 = impulse_space(v3, W3, 0.5, **kw)
    s2 = impulse_space([-1.0, 1.0], np.diag([1.0, 3.5]), 0.5, **kw)
    assert s3.dim == 3 and s3.basis.shape == (3, 2)
    np.testing.assert_allclose(s3.basis[:, 1], [0.0, 0.6, 0.8])
    np.testing.assert_allclose(s3.ellipse, s2.ellipse, atol=1e-12)
    np.testing.assert_allclose(s3.P_II, s2.P_II, atol=1e-12)
    for key in s2.reach:
        np.testing.assert_allclose(s3[key].P, s2[key].P, atol=1e-9, err_msg=key)
        np.testing.assert_array_equal(s3[key].energy_gain, s2[key].energy_gain)
    # sphere, mu = 0.5, e = 0.5: K&L and Routh stick, P_T = -0.285714 (DESIGN §5), and in
    # contact space the tangential impulse opposes the slip (0.6, 0.8)
    for key in ("kane_levinson", "routh"):
        r = s3[key]
        i = r.at(0.5)
        assert r.params["e"][i] == 0.5
        assert r.P[i, 1] == pytest.approx(-0.285714, abs=1e-6)
        np.testing.assert_allclose(r.P_full[i, 1:], -0.285714 * np.array([0.6, 0.8]), atol=1e-6)
        np.testing.assert_allclose(r.v_f[i, 1:], 0.0, atol=1e-9)


def test_3d_swerve_shadow_ellipse():
    """DESIGN swerve case: impulses leave the plane; the drawn ellipse is the shadow of the
    3D no-energy-creation ellipsoid: its rim lifts to dE = 0, and every impulse that
    creates no energy projects inside it."""
    W = np.array([[5.0, 1.0, -1.0], [1.0, 8.0, -2.0], [-1.0, -2.0, 3.0]])
    v = np.array([-4.0, -2.0, 1.0])
    s = impulse_space(v, W, 0.2, laws=("kane_levinson", "routh", "chatterjee_ruina"), n=40,
                      n_grid=7)
    t = np.array([-2.0, 1.0]) / np.sqrt(5.0)
    np.testing.assert_allclose(s.basis[1:, 1], t)
    np.testing.assert_allclose(s.basis.T @ s.basis, np.eye(2), atol=1e-15)
    scale = -s.dE_min
    assert np.abs(s.dE(s.ellipse_full)).max() < 1e-12 * scale
    np.testing.assert_allclose(s.ellipse_full @ s.basis, s.ellipse, atol=1e-12)
    np.testing.assert_allclose(s.P_II, s.P_II_full @ s.basis)
    assert s.dE(s.P_II_full) == pytest.approx(s.dE_min)
    # shadow: plane quadratic with the Schur complement of W
    Q = np.column_stack([s.basis, [0.0, -t[1], t[0]]])
    Wq = Q.T @ W @ Q
    Wp = np.linalg.inv(np.linalg.inv(Wq)[:2, :2])
    vp = s.basis.T @ v
    assert np.abs(s.ellipse @ vp + 0.5 * np.einsum("ni,ij,nj->n", s.ellipse, Wp, s.ellipse)
                  ).max() < 1e-12 * scale
    for r in s.reach.values():
        assert r.P_full.shape[1] == 3
        np.testing.assert_allclose(r.P, r.P_full @ s.basis, atol=1e-15)
        ok = ~r.energy_gain
        q = r.P[ok]
        assert (q @ vp + 0.5 * np.einsum("ni,ij,nj->n", q, Wp, q) <= 1e-12 * scale).all()
    # DESIGN: Routh-energetic at e = 0.2 is (0.763128, 0.039953, -0.203942); K&L sticks
    kl = impulse_space(v, W, 0.2, laws=("kane_levinson",), n=11)["kane_levinson"]
    np.testing.assert_allclose(kl.v_f[kl.at(0.2)], [0.8, 0.0, 0.0], atol=1e-6)


def test_bad_input():
    with pytest.raises(ValueError, match="no impact"):
        impulse_space([0.5, 1.0], ROD, MU)
    with pytest.raises(ValueError, match="unknown law"):
        impulse_space(V1B, ROD, MU, laws=("newton",))
    with pytest.raises(ValueError, match="mu"):
        impulse_space(V1B, ROD, -0.1)
    with pytest.raises(ValueError, match="positive definite"):
        impulse_space(V1B, [[1.0, 2.0], [2.0, 1.0]], MU)
    with pytest.raises(ValueError, match="range"):
        impulse_space(V1B, ROD, MU, laws=("brach",), ranges={"brach": {"e": (-2.0, 1.0)}})


def _count(ax):
    return len(ax.lines), len(ax.collections), len(ax.patches)


def test_plot_writes_png_with_all_artists(case1b, tmp_path):
    from matplotlib.image import imread
    path = tmp_path / "region.png"
    fig = case1b.plot(path)
    ax = fig.axes[0]
    curves = sum(r.kind == "curve" for r in case1b.reach.values())      # 5
    regions = sum(r.kind == "region" for r in case1b.reach.values())    # 2
    # lines: ellipse, cone, P_I, P_II, 2 P_II, curves, region outlines;
    # collections: energy-creating points; patches: ellipse fill + region fills
    assert _count(ax) == (5 + curves + regions, 1, 1 + regions)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    for r in case1b.reach.values():
        assert any(r.label in lab for lab in labels), r.label
    assert any("energy created" in lab for lab in labels)
    assert any("P_I" in lab for lab in labels) and any("P_II" in lab for lab in labels)
    assert "[N s]" in ax.get_xlabel() and "[N s]" in ax.get_ylabel()
    assert "P_T" in ax.get_xlabel() and "P_N" in ax.get_ylabel()
    assert "mu = 0.3" in ax.get_title() and "v = (-1, 1)" in ax.get_title()
    # P_T horizontal, P_N vertical: the ellipse line's data are (P_T, P_N)
    x, y = ax.lines[0].get_data()
    np.testing.assert_allclose(x[:-1], case1b.ellipse[:, 1])
    np.testing.assert_allclose(y[:-1], case1b.ellipse[:, 0])
    assert path.stat().st_size > 20_000
    img = imread(path)
    assert img.shape[0] > 400 and img.shape[1] > 600
    assert img[..., :3].std() > 0.05                          # not blank
    red = (img[..., 0] > 0.9) & (img[..., 1] < 0.2) & (img[..., 2] < 0.2)
    assert red.sum() > 20                                     # energy markers drawn
    with_points = case1b.plot(None, show_grid_points=True)
    assert _count(with_points.axes[0]) == (5 + curves + regions, 1 + regions, 1 + regions)


def test_plot_without_energy_gain_has_no_marker_collection(case1b_frictionless, tmp_path):
    fig = case1b_frictionless.plot(tmp_path / "f.png")
    assert _count(fig.axes[0]) == (5 + 5 + 2, 0, 3)
    assert (tmp_path / "f.png").stat().st_size > 10_000


def test_report_text_and_plot(tmp_path):
    path = tmp_path / "r.png"
    text = impulse_space_report(V1B, ROD, MU, n=60, plot=str(path))
    assert path.stat().st_size > 10_000
    for s in ("P_I  = (0.4, 0)", "P_II = (0.25, -0.25)", "2 P_II = (0.5, -0.5)", "mu = 0.3",
              "Kane & Levinson", "Smith", "Routh (energetic)", "Routh (poisson)", "Brach",
              "Chatterjee & Ruina", "(0.875, 0.125)", str(path)):
        assert s in text, s
    kl = next(ln for ln in text.splitlines() if ln.strip().startswith("Kane & Levinson"))
    assert "YES" in kl and "+0.0625" in kl
    for name in ("Smith", "Routh (energetic)", "Chatterjee & Ruina"):
        ln = next(ln for ln in text.splitlines() if ln.strip().startswith(name))
        assert "YES" not in ln and " no " in ln, ln


def test_package_exports_the_function():
    import rbimpact.impulse_region  # noqa: F401  (the module has its own name)
    assert rbimpact.impulse_space is impulse_space
    assert isinstance(rbimpact.impulse_space(V1B, ROD, MU, laws=("chatterjee_ruina",), n=8,
                                             n_grid=3), ImpulseSpace)


def test_import_does_not_load_matplotlib():
    code = ("import sys, rbimpact, rbimpact.impulse_region; rbimpact.impulse_space; "
            "assert 'matplotlib' not in sys.modules, 'matplotlib imported'")
    subprocess.run([sys.executable, "-c", code], check=True)
