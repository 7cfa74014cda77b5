"""Run a function in a fresh Python process and get its JSON-able result back.

After fmi2Fatal the FMI standard considers every instance of the FMU in the process corrupted,
and with pythonfmu 0.7 that is literally so (it releases Python objects it still points to).
Checks that provoke fatal errors on purpose therefore run here, in a child process, so the
caller (a test session, `pidamper stress`) keeps a clean FMU state.
"""
import json
import subprocess
import sys


def call(function, *args, timeout=300):
    """function: 'module:name' importable in the child; returns what it returns (JSON)."""
    module, name = function.split(":")
    code = ("import json, sys, importlib\n"
            f"result = getattr(importlib.import_module({module!r}), {name!r})(*json.loads(sys.argv[1]))\n"
            "print('\\n@@RESULT@@' + json.dumps(result))\n")
    done = subprocess.run([sys.executable, "-c", code, json.dumps(list(args))], capture_output=True, text=True,
                          timeout=timeout)
    marker = done.stdout.rfind("@@RESULT@@")
    if marker < 0:
        raise RuntimeError(f"{function} failed in its child process (exit {done.returncode}):\n"
                           f"{done.stderr[-3000:]}")
    return json.loads(done.stdout[marker + len("@@RESULT@@"):])
