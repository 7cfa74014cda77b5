"""find_fmu builds a missing or stale FMU once, whoever asks at the same time."""
import subprocess
import sys
import textwrap

import fmpy

from build_fmu import expected_guid

# A process that asks find_fmu for the FMU in FOLDER, counting the builds it starts in FOLDER/builds.
ASK = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from pidamper.running import fmu

    folder = Path(sys.argv[1])
    fmu.default_fmu_path = lambda: folder / fmu.FMU_NAME
    original = fmu.build_fmu

    def counted(out_dir):
        with open(folder / "builds", "a") as log:
            log.write("build\\n")
        return original(out_dir)

    fmu.build_fmu = counted
    while time.time() < float(sys.argv[2]):  # start together
        time.sleep(0.001)
    print(fmu.find_fmu())
""")


def test_two_processes_asking_at_once_get_one_build(tmp_path):
    """Both processes find the FMU missing at the same instant; the file lock lets one build it and
    the other reuse it: one build, the same valid and current FMU for both (without the lock both
    build, and one may open a file the other is still writing)."""
    import time

    start = time.time() + 3.0
    procs = [subprocess.Popen([sys.executable, "-c", ASK, str(tmp_path), str(start)], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert all(p.returncode == 0 for p in procs), outs
    paths = {out.strip() for out, _ in outs}
    assert paths == {str(tmp_path / "PendulumImpactDamper.fmu")}
    assert (tmp_path / "builds").read_text().count("build") == 1
    path = paths.pop()
    assert fmpy.read_model_description(path).guid == expected_guid()
    assert not fmpy.validation.validate_fmu(path)
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".build-")], "a staging folder was left behind"
