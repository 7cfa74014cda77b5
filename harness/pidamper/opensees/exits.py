"""OpenSees ending the process, caught.  Some OpenSees errors call C `exit()` from inside an `ops`
command (a model that calls `modalDamping` and then adds a node ends so, with status 0, in its first
analysis step): no Python `try` sees it, the interpreter is gone without a word.

`guarded(on_exit)` registers a C exit handler for the duration of a `with` block (`__cxa_atexit`
of the Itanium C++ ABI, keyed to a handle of its own): if the process exits inside the block, the
handler calls on_exit(status) (report, hand the completed steps to the logs) and leaves by
os._exit(2), so the exit is a failure.  When the block closes, `__cxa_finalize` on that key runs the
handler once as a no-op and removes it: the interpreter's own exit never meets it (a Python
callback after the interpreter's teardown would crash).  Where the C library has neither function
(Windows), the block guards nothing.
"""
import contextlib
import ctypes
import os
import sys

_HANDLER = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_int)  # void (*)(void *arg, int status)
#: exit status of a run that OpenSees ended
STATUS = 2


def _libc():
    try:
        libc = ctypes.CDLL(None)
        register, finalize = libc.__cxa_atexit, libc.__cxa_finalize
    except (OSError, AttributeError, TypeError):
        return None
    register.argtypes, register.restype = [_HANDLER, ctypes.c_void_p, ctypes.c_void_p], ctypes.c_int
    finalize.argtypes, finalize.restype = [ctypes.c_void_p], None
    return register, finalize


@contextlib.contextmanager
def guarded(on_exit):
    """A block in which a C exit() calls on_exit(status) and ends the process with STATUS."""
    libc = _libc()
    armed = [True]

    def handler(_arg, status):
        if not armed[0]:
            return
        try:
            on_exit(status)
        except BaseException as err:  # the report itself failed: say so, still end as a failure
            print(f"(reporting OpenSees's exit failed: {err!r})", file=sys.__stderr__)
        finally:
            for stream in (sys.stdout, sys.stderr):
                with contextlib.suppress(Exception):
                    stream.flush()
            os._exit(STATUS)

    if libc is None:
        yield
        return
    register, finalize = libc
    thunk, key = _HANDLER(handler), ctypes.create_string_buffer(1)  # both alive until the block closes
    register(thunk, None, ctypes.addressof(key))
    try:
        yield
    finally:
        armed[0] = False
        finalize(ctypes.addressof(key))
