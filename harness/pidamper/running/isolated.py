"""Run a function in a fresh Python process and get its JSON-able result back.

The FMU's native layer answers refused calls with fmi2Error and keeps the process sound; an FMU
without it (pythonfmu's plain binary) answers fmi2Fatal, after which pythonfmu 0.7 has released
Python objects it still points to.  Checks that provoke refusals on purpose therefore run here,
in a child process, so the caller (a test session, `pidamper stress`) keeps a clean process
whichever FMU it checks.  OpenSeesPy runs there too in the test session (`hard_exit`): its library
tears itself down at interpreter exit ("Process 0 Terminating"), and once in CI that teardown
crashed a long test process after every test had passed; a child that leaves by os._exit once its
result is out has no teardown to crash.
"""
import json
import subprocess
import sys


def call(function, *args, timeout=300, hard_exit=False):
    """function: 'module:name' importable in the child; returns what it returns (JSON).  hard_exit:
    the child leaves by os._exit(0) once its result is printed (no interpreter teardown)."""
    module, name = function.split(":")
    code = ("import json, sys, importlib\n"
            f"result = getattr(importlib.import_module({module!r}), {name!r})(*json.loads(sys.argv[1]))\n"
            "print('\\n@@RESULT@@' + json.dumps(result))\n")
    if hard_exit:
        code += "import os\nsys.stdout.flush()\nos._exit(0)\n"
    done = subprocess.run([sys.executable, "-c", code, json.dumps(list(args))], capture_output=True, text=True,
                          timeout=timeout)
    marker = done.stdout.rfind("@@RESULT@@")
    if marker < 0:
        raise RuntimeError(f"{function} failed in its child process (exit {done.returncode}):\n"
                           f"{done.stderr[-3000:]}")
    return json.loads(done.stdout[marker + len("@@RESULT@@"):])
