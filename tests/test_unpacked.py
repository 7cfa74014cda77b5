"""An FMU is unpacked once per process and FMU file (running/unpacked.py): runs and instances share
the folder, a changed file is unpacked anew, and the folders go when the process that made them
exits, not when a forked child does."""
import os
import shutil
import subprocess
import sys
import textwrap

import fmpy
import numpy as np

from pidamper import forcing, run
from pidamper.running.instance import FmuInstance
from pidamper.running.unpacked import unpacked


def test_one_folder_per_file_until_it_changes(fmu_dir, tmp_path):
    path = tmp_path / "model.fmu"
    shutil.copy(fmu_dir / "PendulumImpactDamper.fmu", path)
    folder, md = unpacked(path)
    assert md.modelName == "PendulumImpactDamper"
    assert os.path.isfile(os.path.join(folder, "modelDescription.xml"))
    assert unpacked(str(path))[0] == folder  # the same file: the same folder, whatever the path's type
    shutil.copy(fmu_dir / "ShearBuilding1.fmu", path)  # another FMU in its place
    os.utime(path, ns=(0, os.stat(path).st_mtime_ns + 1))
    again, md2 = unpacked(path)
    assert again != folder and md2.modelName == "ShearBuilding1"
    assert os.path.isdir(folder), "an instance may still run from the earlier folder"


def test_instances_and_runs_share_it_and_agree_with_fmpy_on_the_file(fmu_path):
    with FmuInstance(fmu_path, {"mu": 0.02}) as first:
        folder = first.dir
    with FmuInstance(fmu_path, {"mu": 0.02}) as second:  # the first's close left the files
        assert second.dir == folder
        second.do_step(0.0, 0.01)
    signal = forcing.harmonic(0.0981, 3.132)
    ours = run({"mu": 0.02, "FR": 5.0}, signal, stop_time=2.0, output_interval=0.01, fmu=fmu_path)
    direct = fmpy.simulate_fmu(str(fmu_path), stop_time=2.0, output_interval=0.01, step_size=0.01,
                               start_values={"mu": 0.02, "FR": 5.0, **signal.start_values},
                               input=signal.input_array(0.01 * np.arange(201)), output=["theta", "x"])
    for name in ("theta", "x"):
        assert np.array_equal(ours.data[name], direct[name])


EXITS = textwrap.dedent("""
    import os, sys
    from pidamper.running.unpacked import unpacked
    folder, _ = unpacked(sys.argv[1])
    pid = os.fork()
    if pid == 0:
        sys.exit(0)  # a forked child's exit runs the inherited atexit hook
    os.waitpid(pid, 0)
    print(folder, os.path.isdir(folder))
""")


def test_the_process_that_made_the_folder_removes_it(fmu_path):
    done = subprocess.run([sys.executable, "-c", EXITS, str(fmu_path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    folder, after_child = done.stdout.split()
    assert after_child == "True", "the child removed its parent's folder"
    assert not os.path.exists(folder)
