"""find_fmu finds the FMU of each model, building a missing or stale one once, whoever asks at the
same time; it refuses a storey count no FMU has."""
import os
import subprocess
import sys
import textwrap

import fmpy
import pytest

from build_fmu import expected_guid

# A process that asks find_fmu(storeys=N) for the FMU in FOLDER (PIDAMPER_FMU_DIR), counting the
# builds it starts in FOLDER/builds.
ASK = textwrap.dedent("""
    import sys, time
    from pidamper.running import fmu

    original = fmu.build_fmu

    def counted(out_dir, models):
        with open(f"{out_dir}/builds", "a") as log:
            log.write(" ".join(models) + "\\n")
        return original(out_dir, models)

    fmu.build_fmu = counted
    while time.time() < float(sys.argv[1]):  # start together
        time.sleep(0.001)
    print(fmu.find_fmu(storeys=int(sys.argv[2])))
""")


@pytest.mark.parametrize("storeys,model", [(0, "PendulumImpactDamper"), (4, "DampedShearBuilding4")])
def test_two_processes_asking_at_once_get_one_build(tmp_path, storeys, model):
    """Both processes find the FMU missing at the same instant; the file lock lets one build it and
    the other reuse it: one build, the same valid and current FMU for both (without the lock both
    build, and one may open a file the other is still writing)."""
    import time

    start = time.time() + 3.0
    env = {**os.environ, "PIDAMPER_FMU_DIR": str(tmp_path)}
    procs = [subprocess.Popen([sys.executable, "-c", ASK, str(start), str(storeys)], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, env=env) for _ in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert all(p.returncode == 0 for p in procs), outs
    paths = {out.strip() for out, _ in outs}
    assert paths == {str(tmp_path / f"{model}.fmu")}
    assert (tmp_path / "builds").read_text() == f"{model}\n"
    path = paths.pop()
    assert fmpy.read_model_description(path).guid == expected_guid(model=model)
    assert not fmpy.validation.validate_fmu(path)
    assert sorted(p.name for p in tmp_path.glob("*.fmu")) == [f"{model}.fmu"]  # that variant only
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".build-")], "a staging folder was left behind"


@pytest.mark.parametrize("kwargs,expected", [
    ({"storeys": 11}, r"storeys = 11 is not allowed: an integer in 1\.\.10"),
    ({"storeys": -1}, r"storeys = -1 is not allowed: an integer in 1\.\.10"),
    ({"storeys": 2.5}, r"storeys = 2\.5 is not allowed"),
    ({"storeys": 0, "damper": False}, r"damper = False is not allowed with storeys = 0"),
    ({"model": "ShearBuilding"}, r"model 'ShearBuilding' is not allowed"),
])
def test_find_fmu_refuses_what_no_fmu_models(kwargs, expected):
    from pidamper import find_fmu

    with pytest.raises(ValueError, match=expected):
        find_fmu(**kwargs)


@pytest.mark.parametrize("argument", ["0", "11"])
def test_the_builder_refuses_a_storey_count_outside_1_to_10(tmp_path, argument):
    done = subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(tmp_path), "--storeys", argument],
                          capture_output=True, text=True)
    assert done.returncode == 2 and f"--storeys: {argument!r} is not allowed: an integer in 1..10" in done.stderr
    assert not list(tmp_path.iterdir())


def test_the_builder_and_the_physics_agree_on_the_largest_building():
    from build_fmu import MAX_STOREYS
    from pidamper_physics.params import MAX_STOREYS as PHYSICS_MAX

    assert MAX_STOREYS == PHYSICS_MAX
