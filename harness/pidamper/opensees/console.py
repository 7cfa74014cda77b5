"""pidamper's lines on the console, each on a line of its own.  OpenSeesPy writes its messages
through Python's sys.stderr, some without a closing newline ("WARNING - the 'fullGenLapack' eigen
solver is VERY SLOW. ..."), and what pidamper printed next ran on after them.  `tracked()` wraps
sys.stdout and sys.stderr for the command's duration so each knows whether its last line is left
open; `say` closes an open line on either (they share a terminal) before it writes."""
import contextlib
import sys


class _Tracked:
    """A text stream that remembers whether what was last written to it ended its line."""

    def __init__(self, stream):
        self._stream, self.open = stream, False

    def write(self, text):
        if text:
            self.open = not text.endswith("\n")
        return self._stream.write(text)

    def __getattr__(self, name):
        return getattr(self._stream, name)


@contextlib.contextmanager
def tracked():
    """sys.stdout and sys.stderr tracked inside the block."""
    saved = sys.stdout, sys.stderr
    sys.stdout, sys.stderr = _Tracked(sys.stdout), _Tracked(sys.stderr)
    try:
        yield
    finally:
        sys.stdout, sys.stderr = saved


def say(text, error=False):
    """text on a line of its own, on stderr when `error` (else stdout), flushed."""
    for stream in (sys.stdout, sys.stderr):
        if getattr(stream, "open", False):
            stream.write("\n")
        stream.flush()
    out = sys.stderr if error else sys.stdout
    print(text, file=out, flush=True)
