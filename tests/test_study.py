"""Parametric studies: a real Dask cluster, resuming, forced points, Parquet, core against FMU."""
import csv
import math

import pytest

from pidamper.studies.study import frequency_response, key, run_point, run_study

W2 = math.sqrt(9.81)
FREE = {"theta_dot_0": 0.7 * W2, "mu": 0.1, "e": 0.2}


@pytest.mark.timeout(300)
def test_study_through_a_dask_local_cluster(fmu_path, tmp_path):
    from dask import distributed  # a dependency of the package: no skip
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        rows = run_study({"FR": [1.5, 5.0], "d": [0.05, 0.1]}, FREE, out=tmp_path / "s.csv", engine="fmu",
                         scheduler=cluster.scheduler_address, fmu=fmu_path, progress=False)
    assert len(rows) == 4
    for row in rows:
        point = {**FREE, "FR": float(row["FR"]), "d": float(row["d"])}
        local = run_point(point, engine="core")  # the physics core in this process
        assert float(row["damping_printed"]) == local["damping_printed"]
        assert int(row["impacts"]) == local["impacts"]


def test_an_interrupted_study_resumes_without_redoing_rows(tmp_path):
    out = tmp_path / "s.csv"
    run_study({"FR": [1.5]}, FREE, out=out, engine="core", workers=1, progress=False)
    lines = out.read_text().splitlines()
    header = lines[0].split(",")
    first = lines[1].split(",")
    first[header.index("cpu_s")] = "12345.0"  # a mark: a recomputed row would lose it
    out.write_text("\n".join([lines[0], ",".join(first)]) + "\n")
    rows = run_study({"FR": [1.5, 5.0]}, FREE, out=out, engine="core", workers=1, progress=False)
    with out.open() as handle:
        table = list(csv.DictReader(handle))
    assert len(table) == 2 and table[0]["cpu_s"] == "12345.0"
    assert {r["key"] for r in table} == {key({**FREE, "FR": 1.5}), key({**FREE, "FR": 5.0})}
    assert float(rows[1]["damping_printed"]) > 0


def test_forced_point_gives_the_amplitude_ratio(tmp_path):
    point = {"mu": 0.02, "F0": 0.0981, "Omega_ratio": 1.0, "phi": math.pi / 2, "periods": 20}
    row = run_point(point, engine="core")
    assert row["max_theta_undamped"] == pytest.approx(0.62048, abs=1e-5)  # F0/(2 M w2) t at the last crest
    assert row["amplitude_ratio"] == pytest.approx(row["max_theta"] / row["max_theta_undamped"], rel=1e-15)
    assert 0.1 < row["amplitude_ratio"] < 0.5 and math.isnan(row["damping_printed"])
    rows = run_study({"Omega_ratio": [1.0]}, {k: v for k, v in point.items() if k != "Omega_ratio"},
                     out=tmp_path / "f.csv", engine="core", workers=1, parquet=tmp_path / "f.parquet",
                     progress=False)
    import pyarrow.parquet as pq
    table = pq.read_table(tmp_path / "f.parquet").to_pylist()
    assert table[0]["amplitude_ratio"] == float(rows[0]["amplitude_ratio"]) == row["amplitude_ratio"]


def test_core_and_fmu_give_the_same_measures(fmu_path):
    for point in ({**FREE, "FR": 2.0, "d": 0.1}, {"mu": 0.02, "F0": 0.0981, "Omega_ratio": 0.95, "periods": 10}):
        core = run_point(point, engine="core")
        fmu = run_point(point, engine="fmu", fmu=fmu_path)
        for name in ("damping_printed", "damping_exact", "damping_accumulated", "amplitude_ratio", "impacts"):
            assert (core[name] == fmu[name]) or (math.isnan(core[name]) and math.isnan(fmu[name])), name


def test_frequency_response_without_damper_is_the_undamped_steady_state():
    curve = frequency_response({"mu": 0.02, "F0": 0.0981}, [0.5, 1.0, 1.5], periods=60, settle=40)
    M, L2, F0 = 1.0, 1.0, 0.0981
    assert curve[0]["peak_theta_no_damper"] == pytest.approx(F0 / (M * L2 * 0.75 * W2 ** 2), rel=1e-12)
    assert math.isinf(curve[1]["peak_theta_no_damper"])
    assert all(0 < c["peak_theta_damper"] < 1 for c in curve)


def test_a_building_point_is_forced_and_measured_at_the_building_s_own_frequency():
    """A study point with storeys >= 1 forces at Omega_ratio times the building's first natural
    frequency and measures over its periods (not the pendulum primary's sqrt(g / L2)): the
    oracle is numpy's generalized eigenvalue of the shear building's K and M."""
    import numpy as np

    from pidamper.studies.study import _start_values

    masses, k = [2.0e5, 1.5e5, 1.0e5], [9.0e7, 7.0e7, 5.0e7]
    K = np.diag([k[0] + k[1], k[1] + k[2], k[2]]) - np.diag([k[1], k[2]], 1) - np.diag([k[1], k[2]], -1)
    w_1 = math.sqrt(min(np.linalg.eigvals(np.linalg.solve(np.diag(masses), K)).real))
    point = {"storeys": 3, "F0": 1.0e4, "Omega_ratio": 0.9, "mu": 0.02,
             **{f"floor[{i + 1}].m": m for i, m in enumerate(masses)},
             **{f"storey[{i + 1}].k": s for i, s in enumerate(k)}}
    values, w2 = _start_values(point)
    assert w2 == pytest.approx(w_1, rel=1e-12)
    assert values["Omega"] == pytest.approx(0.9 * w_1, rel=1e-12)
    assert abs(w_1 - math.sqrt(9.81)) > 1.0  # the pendulum's frequency would be far off
