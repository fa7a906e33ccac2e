"""Shared check of the campaign-seed regression tests (``test_groove3d``'s ``REST_SEEDS`` and
``SPHERE_HELD_SEEDS``, ``test_three_points3d``'s ``WALL_SEEDS``): a scene of the randomized
drop campaign (``rbimpact stability --scenes N``), run again by its seed, ends right."""


def assert_campaign_ok(dim, seed, energy_gain_max=None):
    """Run campaign scene ``dim:seed`` (``campaign.run_drop``) and check its row: verdict
    "OK" (the row's note as the message), penetration within the row's tolerance ``pen_tol``
    (m) and, when ``energy_gain_max`` is given, energy created at most that (J). Returns the
    row."""
    from rbimpact import campaign
    row = campaign.run_drop(dim, seed)
    assert row.verdict == "OK", row.note
    assert row.penetration <= row.pen_tol
    if energy_gain_max is not None:
        assert row.energy_gain <= energy_gain_max
    return row
