"""The randomized drop campaign (issue 13) and the regressions it found.

The fixed-seed sample (``CI_SCENES`` per dimension) must show no body below a plane, no
energy created by a law that cannot create it, no scene the campaign failed to build and
no failure of a kind not listed in ``KNOWN_OPEN`` (the persistent-contact modes issue 13
still has to build; each is named by the message the stepper gives today).
"""
import math
import re

import numpy as np
import pytest

from rbimpact import Box, Disk, Law, Scene2D, Simulation
from rbimpact.campaign import (ENERGY_RTOL, DropRow, build_scene, build_stack_scene, draw_scene,
                               draw_stack_scene, drop_campaign, pair_gap, run_drop, scene_seed,
                               stack_scene_seed)

CI_SCENES = 200
"""Scenes per dimension of the fixed-seed sample run in CI."""

#: failure messages of the contact modes still missing (issue 13 item 1), one per mode; a
#: scene failing this way stops with an error or reaches max_events: it fails loudly
KNOWN_OPEN = {
    "persistent contact between bodies (a disk or sphere rolling on another): the cluster's "
    "named refusals (a second cluster, a split, a partner outside a moving cluster)":
        r"impacts accumulate at a single contact point of body \d+ \(\w+\) on body"
        r"|persistent body-body contact",
    "accumulation at one point on a plane not holding the body (a 2D vertex on a wall, "
    "a 3D edge pressed by its spin)":
        r"impacts accumulate at a single contact point of body \d+ \(\w+\) on plane",
    "a body held by two planes or two bodies (chatter, stalls)":
        r"the run stalls|status 'max_events'|did not reach simul_tol|still approach after",
    "3D Newton restitution at frictional contacts that jam (the plastic problem solves)":
        r"jam: no solution of their joint Newton-restitution/Coulomb impact found",
    "a body held by two planes: drift into or a missed event at the second plane":
        r"penetration .* in plane [1-9]|missed event|time-of-impact search",
    "pivot that has no consistent contact force": r"no consistent|pivot integrator reached",
    "3D tipping from a face": r"would tip over",
    "3D persistent contact with two planes (a face on one while touching the other; three "
    "or more features on two)":
        r"persistent contact with two planes|persistent contact on two or more planes"
        r"|motion at three or more features on two planes",
    "3D integrated contact limits": r"integrated contact of body|exceeded rot_max_steps",
}
#: failures that are never acceptable: the campaign could not build or check the scene, or
#: the run raised something other than the stepper's own errors
ALWAYS = (r"scene not built", r"check failed")
#: ... nor in a run that ends 'done' (silently wrong)
SILENT = (r"energy created", r"unstable state", r"penetration")


def _classify(rows):
    """(bad rows, counts of known open modes). A row is bad when it shows an invariant
    broken (energy created, unstable rest, a check or build error), sinks while its run
    says 'done' (silently wrong), or fails in a way no open mode explains."""
    bad, known = [], {}
    for r in rows:
        if r.verdict != "FAIL":
            continue
        single_plane = r.layout in ("floor", "resting", "touching", "stack")
        silent = r.status == "done"     # the run did not say it failed
        loud = r.status in ("done", "max_events", "SimulationError", "NoSolutionError")
        if (not loud or any(re.search(p, r.note) for p in ALWAYS)
                or (silent and any(re.search(p, r.note) for p in SILENT))
                or (single_plane and re.search(r"penetration|missed event", r.note))):
            bad.append(r)       # silently wrong, or sinking into the floor: never open
            continue
        for name, pat in KNOWN_OPEN.items():
            if re.search(pat, r.note):
                known[name] = known.get(name, 0) + 1
                break
        else:
            bad.append(r)
    return bad, known


@pytest.mark.parametrize("dim", [2, 3])
def test_fixed_seed_sample_has_no_sinking_no_energy_gain_no_new_failure(dim):
    report = drop_campaign(CI_SCENES, dim=dim, seed=2026)
    bad, known = _classify(report.rows)
    assert not bad, "\n".join(f"{r.reproducer}: {r.note}" for r in bad)
    assert len(report.rows) == CI_SCENES
    # the campaign checked something: every scene ran, most ended 'done'
    done = sum(r.status == "done" for r in report.rows)
    assert done >= 0.6 * CI_SCENES, (done, known)


STACK_CI_SCENES = 3
"""Stack scenes (``--bodies 3``) of the fixed-seed sample run in CI (the axis's scenes that
end in a refusal can run for minutes before it: the axis itself is for campaigns)."""


def test_stack_axis_sample_is_never_silently_wrong():
    """Three random shapes dropped into a stack on a floor (2D): no scene silently wrong
    (ending 'done' with an overlap beyond tolerance, energy created by a law that cannot
    create it), none the campaign fails to build or check, every failure a known open
    mode; the bodies start apart and each above the one below."""
    report = drop_campaign(STACK_CI_SCENES, dim=2, seed=2026, bodies=3)
    assert len(report.rows) == STACK_CI_SCENES
    assert all(r.layout == "stack" and r.shape.count("+") == 2 for r in report.rows)
    bad, known = _classify(report.rows)
    assert not bad, "\n".join(f"{r.reproducer}: {r.note}" for r in bad)
    assert all(r.reproducer.endswith("--bodies 3") for r in report.rows)
    for k in range(STACK_CI_SCENES):
        spec = draw_stack_scene(2, stack_scene_seed(2, 2026, k))
        assert spec == draw_stack_scene(2, stack_scene_seed(2, 2026, k))
        sim, t_end, _ = build_stack_scene(spec)
        s = sim.run(1e-9).sample([0.0])
        for i in range(3):
            lowest = s["y"][0, i] - sim.scene.bodies[i].shape.bounding_radius
            assert lowest >= spec["bodies"][0]["gap"] * (i == 0) - 1e-15
            for j in range(i + 1, 3):
                assert pair_gap(sim, s, 0, i, j) > 0.0
                assert s["y"][0, j] > s["y"][0, i]
    with pytest.raises(ValueError, match="stack axis"):
        drop_campaign(1, dim=3, bodies=3)
    with pytest.raises(ValueError, match="bodies must be 1, 2 or 3"):
        drop_campaign(1, bodies=4)


def test_scene_seeds_are_reproducible_and_distinct():
    a = draw_scene(2, scene_seed(2, 7, 3))
    b = draw_scene(2, scene_seed(2, 7, 3))
    c = draw_scene(2, scene_seed(2, 7, 4))
    assert a == b and a != c
    assert scene_seed(2, 7, 3) != scene_seed(3, 7, 3)


def test_campaign_rejects_bad_arguments():
    with pytest.raises(ValueError, match="positive integer"):
        drop_campaign(0)
    with pytest.raises(ValueError, match="dim must be"):
        drop_campaign(1, dim=4)
    with pytest.raises(ValueError, match="planar axis is 3D drop scenes"):
        drop_campaign(1, dim="both", planar=True)
    with pytest.raises(ValueError, match="planar axis is 3D drop scenes"):
        drop_campaign(1, dim=3, bodies=2, planar=True)
    with pytest.raises(ValueError, match="planar scenes are 3D"):
        draw_scene(2, 1, planar=True)


@pytest.mark.parametrize("k", range(40))
def test_planar_axis_draws_the_same_scene_made_planar(k):
    """The planar axis (session 14: the thin capsule falling over failed only in planar
    scenes, where a slip-direction scan met an exact zero): the same draw with the
    orientation a unit rotation about y, the velocity in the xz plane and the spin about y;
    everything else as drawn; reproducible, and the reproducer says --planar."""
    sd = scene_seed(3, 0, k)
    a, p = draw_scene(3, sd), draw_scene(3, sd, planar=True)
    assert p == draw_scene(3, sd, planar=True) and p["planar"] and "planar" not in a
    for key in a:
        if key not in ("orientation", "velocity", "spin"):
            assert p[key] == a[key], key
    q = np.array(p["orientation"])
    assert q[1] == 0.0 and q[3] == 0.0 and abs(np.linalg.norm(q) - 1.0) < 1e-15
    assert p["velocity"][1] == 0.0 and [p["velocity"][0], p["velocity"][2]] == \
        [a["velocity"][0], a["velocity"][2]]
    assert p["spin"] == [0.0, a["spin"][1], 0.0]
    if p["layout"] == "resting":
        assert p["orientation"] == a["orientation"]
    row = DropRow(dim=3, seed=sd, shape=p["shape"], law=p["law"], layout=p["layout"],
                  policy=p["policy"], e=0.0, mu=0.0, height=0.0, verdict="OK", status="done",
                  impacts=0, penetration=0.0, pen_tol=0.0, energy_gain=0.0, wall=0.0, note="",
                  planar=True)
    assert row.reproducer == f"rbimpact stability --replay 3:{sd} --planar"
    sim, _, _ = build_scene(p)
    for b in sim.scene.bodies:           # the built bodies move in the xz plane
        assert b.orientation[1] == 0.0 and b.orientation[3] == 0.0
        assert b.velocity[1] == 0.0 and b.position[1] == 0.0
        assert b.angular_velocity[0] == 0.0 and b.angular_velocity[2] == 0.0


# ---- regressions found by the campaign -------------------------------------------------
PLASTIC = [("kane_levinson", {}), ("brach", {"e_t": 0.0}), ("chatterjee_ruina", {"e_t": 0.0}),
           ("routh", {"restitution": "newton"}), ("smith", {})]


@pytest.mark.parametrize("name,extra", PLASTIC)
@pytest.mark.parametrize("shape", ["disk", "box"])
def test_plastic_impact_leaves_the_body_on_the_floor(name, extra, shape):
    """e = 0 leaves v_fN = -1e-15 m/s of round-off; that is not perforation (the bodies
    used to fall through the floor with status 'done')."""
    scene = Scene2D()
    sh = Disk(0.05) if shape == "disk" else Box(0.2, 0.1)
    scene.add_body(sh, 1.0, (0.0, 0.5), angle=0.3 if shape == "box" else 0.0,
                   velocity=(0.4, -1.0), angular_velocity=5.0)
    scene.add_floor()
    res = Simulation(scene, Law(name, e=0.0, mu=0.3, **extra)).run(3.0)
    assert res.status == "done"
    s = res.sample(np.linspace(0.0, 3.0, 3001))
    lowest = 0.05 if shape == "disk" else 0.0
    if shape == "disk":
        gap = s["y"][:, 0] - 0.05
    else:
        V = np.asarray(sh.vertices)
        c, sn = np.cos(s["angle"][:, 0]), np.sin(s["angle"][:, 0])
        gap = np.min(s["y"][:, 0, None] + sn[:, None] * V[:, 0] + c[:, None] * V[:, 1], axis=1)
    assert gap.min() > -1e-9, gap.min()
    assert abs(gap[-1]) < 1e-9 + lowest * 0          # it ends on the floor
    assert abs(s["vy"][-1, 0]) < 1e-9


def test_brach_negative_e_still_perforates():
    from rbimpact import scenarios
    res = scenarios.get("perforation").simulate()
    imp = res.events[res.events["kind"] == "impact"]
    assert len(imp) == 1 and imp["v_f"][0][0] < 0.0      # went through the barrier
    s = res.sample([res.t_end])
    assert s["x"][0, 0] > 1.0


def test_3d_plastic_sphere_stays_on_the_floor():
    from rbimpact import Scene3D, Sphere
    scene = Scene3D()
    scene.add_body(Sphere(0.05), 1.0, (0, 0, 0.3), velocity=(0.3, 0.1, -1.0),
                   angular_velocity=(1.0, 2.0, 0.0))
    scene.add_floor()
    res = Simulation(scene, Law("kane_levinson", e=0.0, mu=0.3)).run(2.0)
    s = res.sample(np.linspace(0, 2.0, 2001))
    assert res.status == "done"
    assert (s["position"][:, 0, 2] - 0.05).min() > -1e-9
    assert abs(s["position"][-1, 0, 2] - 0.05) < 1e-9


@pytest.mark.parametrize("seed", [2100181339, 1307557239, 617897263])
def test_pivot_pieces_create_no_energy(seed):
    """The recorded pieces of an integrated pivot phase created up to 8e-11 of the scene's
    energy with PIECE_ETOL = 1e-10 m V^2; the campaign's bound is 1e-12."""
    row = run_drop(2, seed)
    assert row.verdict == "OK", row.note
    assert row.energy_gain <= ENERGY_RTOL
    assert math.isfinite(row.penetration) and row.penetration <= row.pen_tol


def test_failed_run_result_names_the_failure():
    """The partial result an exception carries says what failed, never 'done'."""
    from rbimpact.errors import SimulationError
    scene = Scene2D()
    scene.add_body(Box(0.2, 0.1), 1.0, (0.0, 0.5))
    scene.add_floor()
    with pytest.raises(SimulationError) as info:
        Simulation(scene, Law("brach", e=-0.5, mu=0.3)).run(2.0)
    res = info.value.result
    assert res.status == "joint_e"
    assert 0.0 < res.t_end < 2.0


def test_tall_box_sliding_tips_over_onto_its_side():
    """Rest/slide on a face -> pivot on the leading corner (tipping): a 0.1 x 0.4 m box
    sliding at 2 m/s with mu = 1 cannot stay on its face (mu h / 2 > w / 2); it pivots on
    its leading corner and ends lying on its long side (was 'would tip over: not
    supported')."""
    scene = Scene2D()
    scene.add_body(Box(0.1, 0.4), 1.0, (0.0, 0.2), velocity=(2.0, 0.0))
    scene.add_floor()
    res = Simulation(scene, Law("kane_levinson", e=0.0, mu=1.0)).run(3.0)
    assert res.status == "done"
    kinds = list(res.events["kind"])
    assert kinds[:2] == ["contact", "pivot"]
    piv = res.events[res.events["kind"] == "pivot"][0]
    assert piv["point"][0] == pytest.approx(0.05)          # the leading corner
    t = np.linspace(0.0, 3.0, 3001)
    s = res.sample(t)
    assert s["y"][-1, 0] == pytest.approx(0.05, abs=1e-9)  # on its long side
    assert abs(math.cos(s["angle"][-1, 0])) < 1e-9
    E = res.energy(t)
    assert np.max(E - np.minimum.accumulate(E)) <= 1e-12 * E[0]
    # never below the floor
    V = np.asarray(Box(0.1, 0.4).vertices)
    c, sn = np.cos(s["angle"][:, 0]), np.sin(s["angle"][:, 0])
    low = np.min(s["y"][:, 0, None] + sn[:, None] * V[:, 0] + c[:, None] * V[:, 1], axis=1)
    assert low.min() > -1e-9


def test_slow_slip_with_holding_friction_sticks():
    """A box snapped onto its face with a slip of 5e-7 m/s (below the accumulation speed)
    and mu = 10 used to tip, land and snap again 2e5 times; it now sticks at once."""
    row = run_drop(2, 3141116543)
    assert row.verdict == "OK", row.note
    assert row.impacts < 1000


def test_released_corner_does_not_join_a_later_instant():
    """A capsule released tangentially from one end cap lands 0.17 s later on the other: the
    cluster gatherer took the released cap (its tangency at the segment start is a root of
    its gap) as touching while it was 1.3e-4 m above the floor, held it, and the pivot
    constraint pulled the body 1.3e-4 m into the floor (+3.5e-4 of the scene's energy,
    status 'done'). A root from the segment start now joins an instant only if the gap
    there is within gap_tol."""
    row = run_drop(2, 3345655047)
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol and row.energy_gain <= 1e-9


def test_disk_accumulating_on_one_groove_plane_rests_on_both():
    """A disk whose bounces on one plane of a groove accumulate while it touches the other
    plane was settled on the first plane alone and gained 5.5e-7 of the scene's energy
    (status 'done'); it now rests on both planes (static equilibrium, mode 5)."""
    row = run_drop(2, 1348835874)
    assert row.verdict == "OK", row.note
    assert row.energy_gain <= ENERGY_RTOL


@pytest.mark.parametrize("seed", [3959818080, 4222489690])
def test_disk_bouncing_between_groove_walls_falls_under_gravity(seed):
    """A disk bouncing between the two walls of a groove: an impact on one wall cancelled the
    pending accumulation on the other and the disk flew on with the held row's acceleration
    (gravity without its normal part): it floated, and its next accumulation gained 1e-8 to
    1e-7 of the scene's energy, status 'done' (listed for two sessions as silently wrong).
    In flight again it falls under gravity."""
    row = run_drop(2, seed)
    assert row.verdict == "OK", row.note
    assert row.energy_gain <= ENERGY_RTOL


def test_frictionless_spinning_disk_in_a_groove_spins_on_both_walls():
    """Smith, e = 0.3, mu = 0: the disk comes to the bottom of the groove spinning; sliding
    on one wall, it went through the other (1.1 cm, a missed event). It now spins on both
    walls (two held contacts) with its centre fixed."""
    row = run_drop(2, 1380054873)
    assert row.verdict == "OK", row.note


def test_box_with_a_face_on_one_groove_wall_and_a_corner_on_the_other_rests():
    """A frictionless box slides on one groove wall into the other: its face and the corner
    on the second wall are a static equilibrium (three contacts), where the single corner
    impact was repeated 1000 times (its law left v_N = -3e-27 m/s) and the run failed."""
    row = run_drop(2, 991650669)
    assert row.verdict == "OK", row.note


def test_capsule_with_an_end_cap_in_the_bottom_of_a_groove_rests_on_three_contacts():
    """A capsule lying along one groove wall with its lower end cap touching both walls:
    held on the cap's two contacts, it turned about the cap until its other cap landed on
    the wall, every 4e-7 s, until max_events. The three contacts of that instant (the cap on
    both walls, the other cap on one) hold it in static equilibrium: it rests."""
    row = run_drop(2, 7653639)
    assert row.verdict == "OK", row.note
    assert row.impacts < 100


@pytest.mark.parametrize("seed", [3433509673, 3949245397])
def test_3d_corner_starts_to_slip_continuously(seed):
    """A box pivoting on a corner with mu = 10 under a small normal force: its sticking force
    left the cone by the event arm (5e-9 N) and the slip that starts opposite to it
    accelerates at 2.4e-9 m/s^2, below the acceptance SLIP_ACC_TOL |g|; no direction was
    taken as consistent and the run stopped ("no consistent stick/slip/lift-off state").
    The continuous onset (stepper3d.SLIP_ONSET_ANGLE) is now taken."""
    row = run_drop(3, seed)
    assert row.verdict == "OK", row.note       # includes the energy check where it applies
    assert row.penetration <= row.pen_tol


def test_3d_grazing_corner_during_pivot_reaches_the_wall():
    """A box pivoting on the floor in a corner swings a vertex 5.9e-6 m into a wall and out
    again within one integrator step: its gap was positive at both step ends, the event was
    missed and the run said 'done' with the box in the wall (silently wrong). A gap whose
    rate turns from negative to positive over a step now has its minimum located and
    tested (pivot3d._gap_dip)."""
    row = run_drop(3, 1454591205)
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol


def test_3d_edge_that_sticks_keeps_no_slip():
    """A box pivoting on an edge under Chatterjee & Ruina (e = 0, mu = 0.3): its second
    contact stuck by an impulse at that contact alone, which left the first one (already
    sticking) with a slip of 3e-7 m/s. Sticking keeps the contact acceleration zero, so
    that slip stayed and the sticking forces worked on it: +1.3e-10 J (4.9e-9 of the
    scene's energy) in 0.036 s, 'done'. Both contact velocities are now zeroed together
    (stepper3d._pv_stick_edge)."""
    row = run_drop(3, 3654158967)
    assert row.verdict == "OK", row.note
    assert row.energy_gain < 1e-10


@pytest.mark.parametrize("seed", [184805226, 1434133100, 974850801, 821168352])
def test_2d_painleve_jam_takes_an_impact_without_collision(seed):
    """Drops whose impacts leave a corner, a rod end or an ellipse sliding at v_N = 0 where
    sliding has no consistent force (mu = 10: Smith, Brach, Kane & Levinson), on landing
    or on tipping from a sliding face: refused ("painleve") before; the default
    painleve="impact" takes Darboux-Keller's impulse from v_N = 0 and the run ends right
    (no energy created, nothing below the floor)."""
    row = run_drop(2, seed)
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol


@pytest.mark.parametrize("seed", [2983676796, 3901860502, 2442379741])
def test_3d_slide_into_a_painleve_jam_takes_an_impact_without_collision(seed):
    """Boxes and a capsule (mu = 10) sliding on one corner or cap whose slip swerves until
    the normal-force coefficient W_NN - mu u . W_TN reaches 0, the normal force growing
    without bound (a dynamic jam: Genot & Brogliato 1999; Nordmark, Dankowicz & Champneys
    2009): the integrator gave up within 1e-12 of its step and the run was refused
    ("Painleve paradox"). painleve="impact" takes the impact without collision there
    (pivot3d.PE_JAM, stepper3d._jam_approach): event "painleve", an impulse in the
    friction cone that leaves v_N >= 0 and creates no energy, and the run ends right."""
    sim, t_end, max_events = build_scene(draw_scene(3, seed))
    res = sim.run(t_end, max_events=max_events)
    assert res.status == "done"
    iwc = res.events[res.events["kind"] == "painleve"]
    assert len(iwc) >= 1
    P = iwc["P"]
    mu = draw_scene(3, seed)["params"]["mu"]
    assert np.all(P[:, 0] > 0.0)
    assert np.all(np.hypot(P[:, 1], P[:, 2]) <= mu * P[:, 0] * (1.0 + 1e-9))
    assert np.all(iwc["v_f"][:, 0] >= -1e-12 * np.abs(iwc["v_i"]).max())
    row = run_drop(3, seed)        # its checks: nothing below a plane, no energy created
    assert row.verdict == "OK", row.note


def test_3d_two_held_contacts_one_dropped_leaves_a_painleve_slide_that_takes_an_impact():
    """A capsule (Brach, e = 0.8, mu = 10) whose impacts accumulate at both caps: the
    validation drops the cap whose normal force would pull, and the one left slides with
    no consistent force. The impact without collision was tried only when one contact
    was held from the start; it now follows the contacts left (3:3138490391)."""
    row = run_drop(3, 3138490391)
    assert row.verdict == "OK", row.note


def test_3d_touching_spheres_after_a_plastic_impact_do_not_stall():
    """Two touching spheres (Routh, Poisson e = 0, mu = 0.3) in flight: their impact ends
    at v_N = -2.8e-17 m/s (round-off), which the pair's time of impact read as a new
    approach at the same instant, every pass, until "the run stalls at t = 0" (3:3811175237).
    A touching pair's normal rate within TOUCH_RTOL of the centres' speeds is zero."""
    row = run_drop(3, 3811175237)
    assert row.verdict == "OK", row.note


def test_3d_corner_left_on_a_wall_at_zero_normal_speed_does_not_stall():
    """A box (Routh, Poisson e = 0, mu = 0.3) whose corner a plastic impact leaves on a
    wall at v_N = 0: the wall does not push against gravity, so the box flies on with the
    corner touching, and the plane's time of impact read the round-off of the corner's
    rate as an approach at the same instant: "the run stalls" (3:2310587818). A touching
    contact's rate within decisions.TOUCH_RTOL of its speed is zero."""
    row = run_drop(3, 2310587818)
    assert row.verdict == "OK", row.note


@pytest.mark.parametrize("seed, why", [
    (944403545, "a frictionless box sliding on one groove face into the crease: its edge's "
                "impact on the other plane was resolved without the held face, whose "
                "projection drove the edge back at once (1500 impacts at one instant)"),
    (3296689687, "a frictionless box tumbling on one corner in the groove's crease: now "
                 "held on both planes at that corner (two sliding contacts at one point)"),
    (3320154933, "a box settling on a groove face while its edge touched the other plane: "
                 "the snap onto the face (capture) turned the edge 1.2e-9 m into that plane, "
                 "'done'; it is now held on both"),
])
def test_3d_box_in_a_groove_crease(seed, why):
    """3D boxes in a V-groove's crease that stalled or were refused ("motion at three or
    more features on two planes, or at one corner touching both ... is not supported")."""
    row = run_drop(3, seed)
    assert row.verdict == "OK", (why, row.note)
    assert row.penetration <= row.pen_tol


@pytest.mark.parametrize("seed", [526051317, 1527272399])
def test_3d_jammed_simultaneous_impact_names_the_jam(seed):
    """Newton restitution at frictional contacts that jam (mu = 10, e = 0.3: a box's corner
    in a groove's crease; a capsule on the floor against a wall): the joint solve finds no
    solution -- an enumeration of every stick/slip/lift-off mode found none, and a
    continuum for the plastic problem -- and says so, naming the jam and the sequential
    policy, instead of "did not reach simul_tol". Still a FAIL: nothing proves, in 3D,
    that no solution exists."""
    from rbimpact.errors import SimulationError
    sim, t_end, max_events = build_scene(draw_scene(3, seed))
    with pytest.raises(SimulationError) as info:
        sim.run(t_end, max_events=max_events)
    msg = str(info.value)
    assert "jam" in msg and "policy='sequential'" in msg
    assert "the plastic problem (e = 0) of the same contacts has one" in msg


@pytest.mark.parametrize("seed,why", [
    (2574756275, "a plastic impact leaves -1.1e-16 m/s at a vertex of a polygon spinning at "
                 "19 rad/s; the impulse of the next 'impact' no longer changes the state"),
    (3564925253, "an ellipse on a wall, Smith e = 0: its boundary's round-off rate"),
    (937134506, "a polygon face flat against a wall: alternating impacts at one instant drive "
                "its speed to 1e-323 m/s, below any relative round-off"),
])
def test_2d_touching_feature_at_round_off_rate_does_not_stall(seed, why):
    """2D: a touching feature's normal rate within decisions.TOUCH_RTOL of its speed scale
    (decisions.touching_speed: the speed it is computed from, at least sqrt(|g| reach)) is
    zero, never an approach; each of these scenes stalled ("more than stall_events
    consecutive events at one instant") when the plane's time of impact read the sign of
    that round-off."""
    row = run_drop(2, seed)
    assert row.verdict == "OK", (why, row.note)
    assert row.penetration <= row.pen_tol


@pytest.mark.parametrize("seed, why", [
    (441169314, "a capsule (C&R, e = 0) flat against a wall, sliding down it: its gap "
                "acceleration -1.4e-20 m/s^2, omega^2 times the round-off of its tilt"),
    (1307965570, "a rod flat against a wall, the same"),
])
def test_2d_body_flat_on_a_wall_gravity_does_not_push_flies_on(seed, why):
    """2D: a body whose impacts left it flat against a wall that gravity does not push was
    held on one end for the sign of a round-off gap acceleration and refused ("impacts
    accumulate at a single contact point"). Read as zero (decisions.touching_accel) it is
    not held; it slides down the wall, its ends touching at round-off rates, which the time
    of impact now steps over in a few steps (toi2d._round_off_rate_time), not toi_atol at
    a time for ever (2:441169314 then filled 20 GB with trajectory segments)."""
    row = run_drop(2, seed)
    assert row.verdict == "OK", (why, row.note)
    assert row.penetration <= row.pen_tol


def test_2d_ellipse_in_a_corner_at_round_off_rate_is_a_named_refusal():
    """2:1694297867 (an ellipse, K&L e = 0, mu = 10, in a corner) stalled on a round-off
    rate (as above); it now goes on to a state with no consistent contact force, refused
    by name (Painleve), not a stall."""
    row = run_drop(2, 1694297867)
    assert row.verdict == "REFUSED", row.note
    assert "Painleve" in row.note


def test_3d_slip_that_stopped_growing_at_a_phase_start_sticks():
    """A box on an edge (Routh, e = 0.3, mu = 1): its first contact began to slip from
    sticking, then its second contact stuck and a new phase began with the first slip
    (3.5e-7 m/s, below slip_eps) already decelerating. Its growth event arms only while
    the growth is positive, so it slid on for 0.165 s with friction along its blended
    start direction, which no longer opposed the slip: +2.4e-5 W, 2.7e-9 of the scene's
    energy, 'done'. Such a slip now sticks again (stepper3d._pv_validate)."""
    row = run_drop(3, 2990834751)
    assert row.verdict == "OK", row.note
    assert row.energy_gain < 1e-10


def test_3d_capsule_rolling_on_its_cap_keeps_its_energy():
    """A capsule rolling on its cap for 6.3 s (C&R, e = 0, mu = 10: it sticks): the
    integrator's local errors added +4.4e-10 J of 0.4 J (1.07e-9 of the scene's energy,
    over the campaign's 1e-9). A conservative phase is now projected onto its energy after
    every accepted step (pivot3d._keep_energy): the energy stays at its value when the
    contact stuck to round-off, neither created nor lost."""
    spec = draw_scene(3, 3045601098)
    sim, t_end, max_events = build_scene(spec)
    res = sim.run(t_end, max_events=max_events)
    assert res.status == "done"
    ev = res.events
    stick = ev["t"][ev["kind"] == "stick"]
    assert stick.size == 1 and t_end - stick[0] > 6.0     # one long rolling phase
    t = np.linspace(stick[0], t_end, 200)
    E = np.asarray(res.energy(t))
    assert np.max(np.abs(E - E[0])) <= 1e-12 * abs(E[0]) + 1e-13


def test_3d_ball_leaving_a_pending_accumulation_falls_under_gravity():
    """A ball in a corner (floor and wall, Routh, mu = 10, sequential): a wall impact
    cancelled its pending accumulation on the floor, and the ball flew on from the held
    row, whose acceleration lacks its normal part: without gravity it rose 9e-6 m off the
    floor over 2 s and gained 5e-3 J, 'done' (silently wrong). The flight row gets
    gravity back (stepper3d run loop; the 2D twin was fixed in stepper2d._gather)."""
    row = run_drop(3, 3361730246)
    assert row.verdict == "OK", row.note
    assert row.energy_gain <= 1e-12


def test_3d_capsule_held_on_both_groove_planes():
    """A capsule in a groove whose impacts accumulate at one cap on each plane: integrated
    contact now holds a feature on each of two planes (pivot3d, per-contact planes); it
    stopped before with "persistent contact with two planes at once is not supported",
    then with "no consistent stick/slip/lift-off state" (two sticking contacts on two
    planes squeeze each other through their normal forces: pivot3d.cone_interval)."""
    row = run_drop(3, 2611256203)
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol


def test_3d_box_corner_on_both_groove_planes_is_refused_by_name():
    """A box whose impacts accumulate at one corner touching both planes of a groove (the
    groove's edge): the two held contacts were the same point, and the two-plane pivot
    divided by their zero distance (ZeroDivisionError from the compiled loop). One sharp
    corner on two planes is now refused by name (not yet built)."""
    row = run_drop(3, 1702903825)
    assert row.status == "SimulationError"
    assert "at one corner touching both" in row.note


@pytest.mark.parametrize("seed", [393293631, 88305742])
def test_3d_corner_whose_sticking_force_would_pull_slides(seed):
    """A box corner entering integrated contact after a plastic impact: sticking needed a
    pulling normal force, so the contact was dropped although its free normal acceleration
    pointed into the floor; the run stopped with a message of zeros ("normal speed 0 m/s
    while the gap accelerates at 0 m/s^2"). The corner now slides in a consistent
    direction (or, if none exists, the run names the Painleve paradox)."""
    row = run_drop(3, seed)
    assert row.verdict == "OK", row.note       # includes the energy check where it applies
    assert row.penetration <= row.pen_tol


@pytest.mark.parametrize("sseed", [3212628988, 666907150])
def test_stack_body_leaving_a_cluster_flies(sseed):
    """Session 29: a stack-axis scene where one body's last contacts in a moving cluster
    lift while the others stay in contact (was refused: "leaves the cluster", PP_SPLIT).
    The body now leaves the cluster and flies (stepper2d._cl_leave); the scene ends 'done'
    with the campaign's invariants (no overlap of any pair or with the floor beyond
    tolerance, no energy created)."""
    row = run_drop(2, sseed, bodies=3)
    assert row.verdict == "OK", row.note
    assert row.status == "done"


def test_3d_refusal_message_prints_no_nan():
    """3:1517526397 (a box in a groove, mu = 1) stops with a singular contact force system
    in its integrated contact, whose failing step's state is not finite: the message says
    so instead of printing the centre of mass as (nan, nan, nan)."""
    row = run_drop(3, 1517526397)
    assert row.verdict == "FAIL"
    assert "the contact force system is singular" in row.note
    assert "nan" not in row.note.lower()
    assert "not finite" in row.note
