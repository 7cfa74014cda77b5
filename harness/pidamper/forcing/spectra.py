"""Intensity measures of a ground-motion record: PGA, PGV and the elastic response spectrum.

The record is a ground acceleration a_g [m/s2] sampled at t = k dt and linear between samples
(`ground_motion.Record`). Everything here is exact for that piecewise-linear signal:

- `pga(record)`: max |a_g| [m/s2] (the maximum of a piecewise-linear signal is at a sample).
- `pgv(record)`: max |v| [m/s] of the ground velocity v(t) = integral_0^t a_g, from rest; v is
  piecewise quadratic, so its extrema lie at the samples or where a_g crosses zero inside an
  interval, and both are evaluated exactly.
- `response_spectrum(accel, dt, periods, zeta)`: the linear SDOF u'' + 2 zeta w u' + w^2 u =
  -a_g(t), w = 2 pi / T, from rest (u = u' = 0 at t = 0), by the exact recurrence for
  piecewise-linear excitation of Nigam & Jennings (1969), "Calculation of response spectra from
  strong-motion earthquake records", Bulletin of the Seismological Society of America 59(2),
  909-922: [u, u']_{k+1} = A [u, u']_k + B [a_k, a_{k+1}], with A and B functions of
  (w, zeta, dt) only (`nigam_jennings_matrices`: their closed form, or - the default, free of
  its cancellation at small w dt - the same matrices from a matrix exponential), for all periods
  at once (numpy arrays over the periods, one pass over time). The peaks are taken over the
  samples (a peak between samples is missed by at most O((w dt)^2) relative).

  Returned: Sd = max |u| [m], Sv = max |u'| [m/s] (relative velocity), Sa = w^2 Sd [m/s2]: the
  PSEUDO-spectral acceleration, the engineering standard for Sa(T1, 5 %) (e.g. ASCE 7, the PEER
  NGA databases). Also PSv = w Sd [m/s] (pseudo-velocity) and Sa_abs = max |u'' + a_g| =
  max |2 zeta w u' + w^2 u| [m/s2] (the true peak absolute acceleration). At T = 0 (a rigid
  oscillator) Sd = Sv = 0 and Sa = Sa_abs = PGA.
"""
import math

import numpy as np

__all__ = ["pga", "pgv", "ground_velocity", "nigam_jennings_matrices", "sdof_response", "response_spectrum",
           "sa", "sa_avg", "SA_AVG_RANGE"]

#: Sa_avg's periods: SA_AVG_RANGE[2] of them equally spaced over [SA_AVG_RANGE[0], SA_AVG_RANGE[1]]
#: times T1 (Eads, Miranda and Lignos 2015: 0.2 T1 to 3 T1, ten periods)
SA_AVG_RANGE = (0.2, 3.0, 10)


def _accel_dt(record_or_accel, dt=None):
    if dt is None:
        return np.asarray(record_or_accel.accel, dtype=np.float64), float(record_or_accel.dt)
    return np.asarray(record_or_accel, dtype=np.float64), float(dt)


def pga(record):
    """Peak ground acceleration max |a_g| [m/s2] (units of the record)."""
    return float(np.max(np.abs(np.asarray(record.accel))))


def ground_velocity(record):
    """Ground velocity [m/s] at the samples, from rest: v_k = sum of dt (a_j + a_{j+1}) / 2, the
    exact integral of the piecewise-linear acceleration (the trapezoidal rule is exact here)."""
    accel, dt = _accel_dt(record)
    v = np.zeros_like(accel)
    np.cumsum(0.5 * dt * (accel[1:] + accel[:-1]), out=v[1:])
    return v


def pgv(record):
    """Peak ground velocity max_t |v(t)| [m/s], v(t) = integral_0^t a_g (from rest), exact for the
    piecewise-linear acceleration: the samples and, inside each interval where a_g changes sign,
    the extremum at the zero crossing (v_k + a_k s / 2 with s = dt a_k / (a_k - a_{k+1}))."""
    accel, dt = _accel_dt(record)
    v = ground_velocity(record)
    peak = float(np.max(np.abs(v)))
    a0, a1 = accel[:-1], accel[1:]
    cross = np.flatnonzero(a0 * a1 < 0)
    if cross.size:
        s = dt * a0[cross] / (a0[cross] - a1[cross])
        peak = max(peak, float(np.max(np.abs(v[cross] + 0.5 * a0[cross] * s))))
    return peak


def nigam_jennings_matrices(omega, zeta, dt, method="expm"):
    """The exact recurrence of Nigam & Jennings (1969) for u'' + 2 zeta w u' + w^2 u = -a(t), a
    linear between a_k and a_{k+1} over a step dt: [u, u']_{k+1} = A [u, u']_k + B [a_k, a_{k+1}].

    omega: array of w > 0 [rad/s]; 0 <= zeta < 1. Returns (A, B), arrays of shape (2, 2) +
    omega.shape.

    method="closed-form": Nigam & Jennings' closed form. With w_d = w sqrt(1 - zeta^2),
    E = exp(-zeta w dt), S = sin(w_d dt), C = cos(w_d dt), r = zeta / sqrt(1 - zeta^2):
      A11 = E (r S + C),             A12 = E S / w_d,
      A21 = -w E S / sqrt(1-zeta^2), A22 = E (C - r S),
      B11 = E [((2 zeta^2 - 1)/(w^2 dt) + zeta/w) S/w_d + (2 zeta/(w^3 dt) + 1/w^2) C] - 2 zeta/(w^3 dt)
      B12 = -E [(2 zeta^2 - 1)/(w^2 dt) S/w_d + 2 zeta/(w^3 dt) C] - 1/w^2 + 2 zeta/(w^3 dt)
      B21 = E [((2 zeta^2 - 1)/(w^2 dt) + zeta/w)(C - r S) - (2 zeta/(w^3 dt) + 1/w^2)(w_d S + zeta w C)]
            + 1/(w^2 dt)
      B22 = -E [(2 zeta^2 - 1)/(w^2 dt)(C - r S) - 2 zeta/(w^3 dt)(w_d S + zeta w C)] - 1/(w^2 dt)
    Its terms cancel when w dt is small: it loses about eps / (w dt)^3 relative (measured against
    40-digit mpmath: 3e-11 at T = 3 s, dt = 0.005 s; 1.2e-6 at T = 10 s, dt = 0.0005 s; 2.8e-4
    at T = 20 s, dt = 0.0002 s).

    method="expm" (default): the same matrices as the matrix exponential of the augmented
    system d/dt [u, u', a, a'] = [[0, 1, 0, 0], [-w^2, -2 zeta w, -1, 0], [0, 0, 0, 1], [0]*4]
    over dt (scipy.linalg.expm, batched over the periods; the input-integral construction of Van
    Loan 1978, IEEE Trans. Automatic Control 23(3), 395-404): A = E[:2, :2], B = [E[:2, 2] -
    E[:2, 3] / dt, E[:2, 3] / dt]. No cancellation: within 1.5e-12 relative (each B entry; A
    relative to its row) of 40-digit mpmath over T = 0.02 .. 20 s, dt = 0.0002 .. 0.02 s with
    dt <= T / 2, zeta = 0 .. 0.2."""
    w = np.asarray(omega, dtype=np.float64)
    zeta = float(zeta)
    dt = float(dt)
    if method == "expm":
        from scipy.linalg import expm

        M = np.zeros(w.shape + (4, 4))
        M[..., 0, 1] = dt
        M[..., 1, 0] = -w * w * dt
        M[..., 1, 1] = -2 * zeta * w * dt
        M[..., 1, 2] = -dt
        M[..., 2, 3] = dt
        E = expm(M) if w.ndim else expm(M[None])[0]
        A = np.moveaxis(E[..., :2, :2], (-2, -1), (0, 1))
        ramp = E[..., :2, 3] / dt
        B = np.stack([E[..., :2, 2] - ramp, ramp], axis=-1)
        return A, np.moveaxis(B, (-2, -1), (0, 1))
    if method != "closed-form":
        raise ValueError(f"method = {method!r} is not allowed: expected 'expm' or 'closed-form'")
    root = math.sqrt(1.0 - zeta * zeta)
    wd = w * root
    E = np.exp(-zeta * w * dt)
    S = np.sin(wd * dt)
    C = np.cos(wd * dt)
    r = zeta / root
    A = np.array([[E * (r * S + C), E * S / wd],
                  [-w / root * E * S, E * (C - r * S)]])
    w2dt = w * w * dt
    w3dt = w2dt * w
    k1 = (2 * zeta * zeta - 1) / w2dt
    k2 = 2 * zeta / w3dt
    cr = C - r * S
    sd = wd * S + zeta * w * C
    B = np.array([[E * ((k1 + zeta / w) * S / wd + (k2 + 1 / (w * w)) * C) - k2,
                   -E * (k1 * S / wd + k2 * C) - 1 / (w * w) + k2],
                  [E * ((k1 + zeta / w) * cr - (k2 + 1 / (w * w)) * sd) + 1 / w2dt,
                   -E * (k1 * cr - k2 * sd) - 1 / w2dt]])
    return A, B


def _prepare(accel, dt, periods, zeta):
    accel = np.asarray(accel, dtype=np.float64)
    if accel.ndim != 1 or accel.size < 1 or not np.all(np.isfinite(accel)):
        raise ValueError("accel is not allowed: expected a 1-D array of finite samples [m/s2]")
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt = {dt!r} is not allowed: it must be a finite number > 0 s")
    zeta = float(zeta)
    if not (0.0 <= zeta < 1.0):
        raise ValueError(f"zeta = {zeta!r} is not allowed: expected 0 <= zeta < 1 (an underdamped oscillator)")
    periods = np.asarray(periods, dtype=np.float64)
    if not np.all(np.isfinite(periods)) or np.any(periods < 0):
        raise ValueError("periods are not allowed: expected finite periods >= 0 s")
    return accel, dt, periods, zeta


def sdof_response(accel, dt, periods, zeta=0.05, method="expm"):
    """The relative displacement u [m] and velocity u' [m/s] of the SDOF oscillators (periods [s],
    all > 0) at every sample, from rest, by the Nigam-Jennings recurrence: arrays of shape
    (len(accel),) + periods.shape. (`response_spectrum` computes the same without storing.)"""
    accel, dt, periods, zeta = _prepare(accel, dt, periods, zeta)
    if np.any(periods <= 0):
        raise ValueError("periods are not allowed: sdof_response needs periods > 0 s")
    A, B = nigam_jennings_matrices(2 * math.pi / periods, zeta, dt, method)
    u = np.zeros((accel.size,) + periods.shape)
    v = np.zeros_like(u)
    for k in range(accel.size - 1):
        a0, a1 = accel[k], accel[k + 1]
        u[k + 1] = A[0, 0] * u[k] + A[0, 1] * v[k] + B[0, 0] * a0 + B[0, 1] * a1
        v[k + 1] = A[1, 0] * u[k] + A[1, 1] * v[k] + B[1, 0] * a0 + B[1, 1] * a1
    return u, v


def response_spectrum(accel, dt, periods, zeta=0.05, method="expm"):
    """Elastic response spectrum of a piecewise-linear accelerogram (accel [m/s2] sampled every dt
    [s]) at `periods` [s] (>= 0; scalar or array) and damping ratio zeta (0 <= zeta < 1): a dict of
    arrays shaped like periods, Sd [m], Sv [m/s] (relative velocity), Sa = w^2 Sd [m/s2]
    (pseudo-acceleration), PSv = w Sd [m/s], Sa_abs [m/s2] (true absolute acceleration), all
    maxima over the samples of the oscillator started from rest (Nigam & Jennings 1969; module
    docstring). One pass over time, vectorised over the periods. method: see
    `nigam_jennings_matrices`."""
    accel, dt, periods, zeta = _prepare(accel, dt, periods, zeta)
    shape = periods.shape
    T = periods.ravel()
    live = T > 0
    w = np.zeros_like(T)
    w[live] = 2 * math.pi / T[live]
    wl = w[live]
    A, B = nigam_jennings_matrices(wl, zeta, dt, method)
    a11, a12, a21, a22 = A[0, 0], A[0, 1], A[1, 0], A[1, 1]
    b11, b12, b21, b22 = B[0, 0], B[0, 1], B[1, 0], B[1, 1]
    u = np.zeros_like(wl)
    v = np.zeros_like(wl)
    umax = np.zeros_like(wl)
    vmax = np.zeros_like(wl)
    amax = np.zeros_like(wl)
    c_u, c_v = wl * wl, 2 * zeta * wl
    for k in range(accel.size - 1):
        a0, a1 = accel[k], accel[k + 1]
        u, v = a11 * u + a12 * v + b11 * a0 + b12 * a1, a21 * u + a22 * v + b21 * a0 + b22 * a1
        np.maximum(umax, np.abs(u), out=umax)
        np.maximum(vmax, np.abs(v), out=vmax)
        np.maximum(amax, np.abs(c_u * u + c_v * v), out=amax)
    peak = float(np.max(np.abs(accel)))
    out = {name: np.zeros_like(T) for name in ("Sd", "Sv", "Sa", "PSv", "Sa_abs")}
    out["Sd"][live] = umax
    out["Sv"][live] = vmax
    out["Sa"][live] = wl * wl * umax
    out["PSv"][live] = wl * umax
    out["Sa_abs"][live] = amax
    out["Sa"][~live] = peak
    out["Sa_abs"][~live] = peak
    return {name: (value.reshape(shape) if shape else float(value[0])) for name, value in out.items()}


def sa(record, T, zeta=0.05):
    """Sa(T, zeta) [m/s2] of a Record: the pseudo-spectral acceleration (2 pi / T)^2 Sd, the
    intensity measure Sa(T1, 5 %) of a performance-based assessment. Scalar T -> float."""
    return response_spectrum(record.accel, record.dt, T, zeta)["Sa"]


def sa_avg(record, T1, zeta=0.05, span=SA_AVG_RANGE):
    """Sa_avg(T1, zeta) [m/s2] of a Record: the geometric mean of Sa over `span` = (lo, hi, n): n
    periods equally spaced from lo T1 to hi T1 (Eads, Miranda & Lignos 2015, "Average spectral
    acceleration as an intensity measure for collapse risk assessment", Earthquake Engineering &
    Structural Dynamics 44(12): 0.2 T1 to 3 T1, ten periods), all in one pass of the spectrum."""
    lo, hi, n = span
    values = response_spectrum(record.accel, record.dt, np.linspace(lo * T1, hi * T1, int(n)), zeta)["Sa"]
    return float(np.exp(np.mean(np.log(values))))
