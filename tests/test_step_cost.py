"""The step-cost benchmark runs every FMU it compares, in fmpy and in the native host, and writes
its page (no timing is asserted: the figures are the benchmark's output, not a test)."""
import re

from pidamper.benchmarks import step_cost


def test_step_cost_measures_every_row_and_writes_its_page(fmu_path, tmp_path):
    import fmpy

    n = sum(v.causality == "output" for v in fmpy.read_model_description(str(fmu_path)).modelVariables)
    step_cost.main(["--steps", "300", "--repeats", "1", "--fmu", str(fmu_path), "--out", str(tmp_path)])
    page = (tmp_path / "step-cost.md").read_text()
    rows = dict(re.findall(r"^\| (.+?) \| (.+) \|$", page, flags=re.M))
    for name in ("compiled C FMU (floor), every output (3)", "trivial pythonfmu FMU, every output (3)",
                 "damper, no contact, three outputs", f"damper, no contact, every output ({n})",
                 f"trivial pythonfmu FMU, every output ({n}: as many as the damper)",
                 f"PendulumImpactDamper.fmu, no contact, every output ({n})",
                 "damper without the native layer, no contact, every output",
                 "damper, no contact (finds Python by itself)",
                 "damper without the native layer (libpython preloaded)"):
        assert name in rows, name
    # the stops never act in the no-contact rows; the contact rows do impact
    assert rows["damper, no contact, three outputs"].endswith("| 0")
    assert int(rows["damper, free decay (FR 5, d 0.1 m, e 0.2, A0 = 0.7 rad), three outputs"].split("|")[-1]) > 20
    # the native host read every output of the pendulum system (no building's outputs any more)
    assert rows["damper, no contact (finds Python by itself)"].startswith(f"{n} |") and n == 13
    assert re.search(r"^\| DampedShearBuilding3\.fmu, at rest, every output \(\d+\) \|", page, flags=re.M)
    assert re.search(r"every output of PendulumImpactDamper\.fmu: \*\*[0-9.]+x\*\* the trivial 3-output", page)
    assert "target <= 1.3" in page and "target <= 2.0" in page and "us** per impact" in page
