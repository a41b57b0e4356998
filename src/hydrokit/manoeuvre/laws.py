"""The manoeuvres' helm logics, the hold autopilot and the approach's steadiness test, written
once on plain floats over small state arrays (issue #50 item 2).

:func:`hydrokit.manoeuvre.run.fly_manoeuvre` (the Python loop, for any right-hand side)
calls these functions as Python; :mod:`hydrokit.manoeuvre.compiled` compiles the same
functions with ``compile_law`` and calls them from its compiled loop — one implementation, two
ways of running it. No numba here, no allocation, no Python objects: floats, ints and arrays.

Arrays (the layouts are the ``P_*``, ``S_*`` and ``K_*`` indices below):

- ``P`` — the logic's settings: kind, A (rad), the surface's limit (rad), the probe ∂(angular
  acceleration)/∂δ (1/s² per rad), L/U at the execute (s), B (rad), M (m), … and the spiral's
  targets (rad or rad/s);
- ``S`` — the logic's memory: done, the executes (s), the state at the execute, phases, …;
- ``H`` — the record the steady tests read, one row per logic call: t (s), rate (rad/s), speed
  (m/s), deflection (rad; the heading change for a turning circle);
- ``R`` — rows the logic writes as it goes: a spiral's points, a pull-out's sides;
- ``K`` — the hold autopilot (:func:`keeper_command`): surfaces, set-points, gains, the three PID
  loops' settings and integrals.
"""

from __future__ import annotations

import math

from hydrokit.core.kinematics import wrap_angle
from hydrokit.manoeuvre import metrics as mm
from hydrokit.model.control import _euler_rates, depth_to_pitch, pid_law

# ---------------------------------------------------------------------------------- settings
#: the heading change (rad) over which a turning circle's steady part is measured (360°)
TURN_WINDOW = mm.STEADY_WINDOW
#: heading change held in a turning circle, rad (the steady part is the last 360°)
TURN_TARGET = mm.STEADY_START + mm.STEADY_WINDOW + math.radians(1.0)
#: the turn is steady when yaw rate and speed vary by at most this fraction over the last 360°
TURN_STEADY = 0.01
#: the longest turn flown while waiting for it to become steady, rad (10 turns)
TURN_MAX = 20.0 * math.pi
#: a spiral or pull-out step is judged steady over windows of this many L/U (U the speed now)
STEADY_WINDOW = 5.0
#: … steady when the rate's means over the last two windows differ by at most this many U/L (rad/s)
STEADY_DRIFT_ABS = 1e-5
#: … plus this fraction of the rate
STEADY_DRIFT_REL = 1e-3
#: a step not steady after this many L/U ends unsettled (its row says settled = false)
STEADY_MAX_HOLD = 100.0
#: largest pitch set-point of the depth hold, rad (20°)
HOLD_MAX_PITCH = math.radians(20.0)
#: time between the depth/heading hold's probes of the surfaces' effect, s
HOLD_PERIOD = 0.5
#: below this speed (m/s) the hold leaves its surfaces at zero (they have no grip)
HOLD_MIN_SPEED = 0.05
#: the approach is steady when the held depth (m) and heading (rad) are this close to their set-points
HOLD_TOLERANCE = 1e-3
#: a closed-loop depth change has settled within this fraction of the change …
DEPTH_BAND = 0.05
#: … and at least this, m
DEPTH_BAND_MIN = 0.05
#: … for this many L/U
DEPTH_SETTLE = 20.0

# kinds of logic
TURN, ZIGZAG, SPIRAL, PULL_OUT, DEPTH_CHANGE, DEPTH_PILOT = 0, 1, 2, 3, 4, 5
#: the pull-out's phases: turn, release, straighten, turn, release
PULL_OUT_PHASES = 5

# P: settings
P_KIND, P_A, P_LIMIT, P_PROBE, P_SCALE, P_CHECK, P_DEPTH, P_ANGLE = 0, 1, 2, 3, 4, 5, 6, 7
P_REVERSE, P_DT, P_RATE, P_NT, P_MAXPITCH, P_TARGETS = 8, 9, 10, 11, 12, 16
#: most spiral targets
MAX_TARGETS = 32
P_SIZE = P_TARGETS + MAX_TARGETS
# S: memory
S_DONE, S_NEXEC, S_EXEC = 0, 1, 2
#: most executes recorded
MAX_EXECUTES = 16
S_X0 = S_EXEC + MAX_EXECUTES  # 12 numbers
S_CMD, S_SIGN, S_PREV, S_PEAK, S_PHASE, S_NEXT, S_K, S_START = 30, 31, 32, 33, 34, 35, 36, 37
S_U0, S_INT, S_H0, S_SENSE, S_REACHED, S_INSIDE, S_BAND = 38, 39, 40, 41, 42, 43, 44
S_LR, S_LU, S_LD, S_LOK, S_STRAIGHT, S_NROWS = 45, 46, 47, 48, 49, 50
S_REL_D, S_REL_R, S_REL_T, S_REL_OK, S_NOTE, S_NOTE_A, S_NH = 51, 52, 53, 54, 55, 56, 57
S_SIZE = 64
#: columns of H and R
H_COLS = 4
R_COLS = 8
#: most rows of R (spiral points, pull-out sides)
MAX_ROWS = MAX_TARGETS
# K: the hold autopilot
K_PLANE, K_RUDDER, K_STEER, K_Z0, K_PSI0, K_NEXT, K_GQ, K_GR = 0, 1, 2, 3, 4, 5, 6, 7
K_KZ, K_TRIM, K_LEN, K_LIMP, K_LIMR, K_ON = 8, 9, 10, 11, 12, 13
#: the three PID loops (depth, pitch, heading) from K_PID, K_PIDW numbers each: kp, ki, kd,
#: output_min, output_max, angle (1/0), integral, previous measurement
K_PID, K_PIDW = 16, 8
K_SIZE = K_PID + 3 * K_PIDW


# ---------------------------------------------------------------------------------- the logics
def helm_init(P, S, x0):  # noqa: ANN001, ANN201
    """Start the logic of ``P`` at the execute state ``x0`` (12 numbers): fill ``S``."""
    for i in range(S.shape[0]):
        S[i] = 0.0
    for i in range(12):
        S[S_X0 + i] = x0[i]
    S[S_NEXEC] = 1.0  # the execute at t = 0
    S[S_EXEC] = 0.0
    S[S_PEAK] = math.nan
    S[S_REACHED] = math.nan
    S[S_INSIDE] = math.nan
    S[S_STRAIGHT] = -1.0
    kind = int(P[P_KIND])
    a = P[P_A]
    S[S_CMD] = a
    if kind == TURN:
        S[S_NEXT] = TURN_TARGET
    elif kind == SPIRAL or kind == PULL_OUT:
        S[S_U0] = math.hypot(x0[6], x0[7])
    elif kind == DEPTH_CHANGE:
        dive = P[P_DEPTH] > 0
        # nose down (q̇ < 0) dives: choose the sign of A that pitches the nose the right way
        s = -1.0 if P[P_PROBE] > 0 else 1.0
        S[S_CMD] = abs(a) * (s if dive else -s)
        S[S_SENSE] = 1.0 if dive else -1.0
    elif kind == DEPTH_PILOT:
        S[S_SENSE] = 1.0 if P[P_DEPTH] > 0 else -1.0
        S[S_BAND] = max(DEPTH_BAND * abs(P[P_DEPTH]), DEPTH_BAND_MIN)


def _execute(S, t):  # noqa: ANN001, ANN202
    n = int(S[S_NEXEC])
    if n < MAX_EXECUTES:
        S[S_EXEC + n] = t
        S[S_NEXEC] = n + 1


def _last_execute(S):  # noqa: ANN001, ANN202
    return S[S_EXEC + int(S[S_NEXEC]) - 1]


def turn_command(P, S, H, t, x):  # noqa: ANN001, ANN201
    """Turning circle: the surface held at A until the heading has changed :data:`TURN_TARGET`
    and the yaw rate and the speed over the last 360° are steady (spread within
    :data:`TURN_STEADY` of their mean, as ITTC asks of the steady turn), or :data:`TURN_MAX`."""
    ang = int(P[P_ANGLE])
    a = abs(x[ang] - S[S_X0 + ang])
    n = int(S[S_NH])
    H[n, 0] = t
    H[n, 1] = x[11]
    H[n, 2] = math.hypot(x[6], x[7])
    H[n, 3] = a
    n += 1
    S[S_NH] = n
    if a >= S[S_NEXT]:
        k = 0
        while H[k, 3] < a - TURN_WINDOW:
            k += 1
        rmin = rmax = H[k, 1]
        umin = umax = H[k, 2]
        rs = us = 0.0
        for i in range(k, n):
            r, u = H[i, 1], H[i, 2]
            rmin, rmax = min(rmin, r), max(rmax, r)
            umin, umax = min(umin, u), max(umax, u)
            rs += r
            us += u
        m = n - k
        steady = rmax - rmin <= TURN_STEADY * abs(rs / m) and umax - umin <= TURN_STEADY * (us / m)
        if steady or a >= TURN_MAX:
            S[S_DONE] = 1.0
            if not steady:
                S[S_NOTE] = 1.0
                S[S_NOTE_A] = a
        S[S_NEXT] = a + math.radians(10.0)
    return P[P_A]


def zigzag_command(P, S, t, x):  # noqa: ANN001, ANN201
    """Zigzag A/B (IMO 4.2.6) on the heading (or the pitch): to −A when the angle has changed by
    B in the direction of the turn, … four executes, and the end a quarter of the last swing
    after the angle has peaked (the third overshoot)."""
    ang = int(P[P_ANGLE])
    b = P[P_CHECK]
    a = x[ang] - S[S_X0 + ang]
    sign = S[S_SIGN]
    n_ex = int(S[S_NEXEC])
    if sign == 0.0:
        if abs(a) >= b:
            S[S_SIGN] = 1.0 if a > 0 else -1.0
            S[S_CMD] = -S[S_CMD]
            _execute(S, t)
    elif n_ex < 4:
        s = sign * a
        odd = n_ex % 2 == 0  # after the 2nd execute the turn goes back
        if (odd and s <= -b) or (not odd and s >= b):
            S[S_CMD] = -S[S_CMD]
            _execute(S, t)
    else:
        s = sign * a
        last = _last_execute(S)
        if math.isnan(S[S_PEAK]) and s < sign * S[S_PREV] and t > last:
            S[S_PEAK] = t
        peak = S[S_PEAK]
        if not math.isnan(peak) and t >= peak + 0.25 * (peak - last) + 1e-9:
            S[S_DONE] = 1.0
    S[S_PREV] = a
    return S[S_CMD]


def scale_now(P, S, x):  # noqa: ANN001, ANN201
    """L/U at the speed now, s (the speed floored at a tenth of the approach speed)."""
    u0 = S[S_U0]
    u = math.hypot(x[6], x[7])
    return P[P_SCALE] * u0 / max(u, 0.1 * u0) if u0 > 0 else P[P_SCALE]


def _mean(H, col, k0, k1):  # noqa: ANN001, ANN202
    s = 0.0
    for i in range(k0, k1):
        s += H[i, col]
    return s / (k1 - k0)


def _record(P, S, H, t, x, cmd):  # noqa: ANN001, ANN202
    """Append the sample; True when the step is over: the means of the rate over the last two
    windows of :data:`STEADY_WINDOW` L/U differ by at most :data:`STEADY_DRIFT_ABS` U/L +
    :data:`STEADY_DRIFT_REL` of the rate (after two windows, judged ten times a window), or the
    step was held :data:`STEADY_MAX_HOLD` L/U. S_LR … S_LOK: the last window's means of rate,
    speed and deflection and whether steady."""
    n = int(S[S_NH])
    H[n, 0] = t
    H[n, 1] = x[int(P[P_RATE])]
    H[n, 2] = math.hypot(x[6], x[7])
    H[n, 3] = cmd
    n += 1
    S[S_NH] = n
    held = t - S[S_START]
    scale = scale_now(P, S, x)
    window = STEADY_WINDOW * scale
    if held < 2.0 * window or t < S[S_NEXT]:
        return False
    S[S_NEXT] = t + 0.1 * window  # judged ten times a window, not every step
    h0 = int(S[S_H0])
    k1 = n
    while k1 > h0 and H[k1 - 1, 0] >= t - window:
        k1 -= 1
    k0 = k1
    while k0 > h0 and H[k0 - 1, 0] >= t - 2.0 * window:
        k0 -= 1
    r1 = _mean(H, 1, k1, n)
    r0 = _mean(H, 1, k0, k1) if k1 > k0 else math.inf
    steady = abs(r1 - r0) <= STEADY_DRIFT_ABS / scale + STEADY_DRIFT_REL * abs(r1)
    S[S_LR] = r1
    S[S_LU] = _mean(H, 2, k1, n)
    S[S_LD] = _mean(H, 3, k1, n)
    S[S_LOK] = 1.0 if steady else 0.0
    return steady or held >= STEADY_MAX_HOLD * scale


def _reset(S, t):  # noqa: ANN001, ANN202
    S[S_H0] = S[S_NH]
    S[S_START] = t
    S[S_NEXT] = t
    S[S_INT] = 0.0


def rate_pilot(P, S, target, x):  # noqa: ANN001, ANN201
    """The surface command (rad) of a yaw-rate autopilot holding ``target`` (rad/s): PI on r
    with natural frequency U/L, its gains over |∂ṙ/∂δ| (probed at the execute, scaled by
    (U/U₀)² as fin forces go), the integral held while the surface is at its limit."""
    scale = scale_now(P, S, x)
    w = 1.0 / scale
    u = math.hypot(x[6], x[7])
    u0 = S[S_U0]
    probe = P[P_PROBE]
    ap = abs(probe) if probe != 0.0 else 1.0
    g = ap * (max(u, 0.1 * u0) / u0) ** 2 if u0 > 0 else 1.0
    e = target - x[int(P[P_RATE])]
    s = 1.0 if probe >= 0 else -1.0
    dt = P[P_DT]
    S[S_INT] += e * dt
    cmd = s * (2.0 * w * e + w * w * S[S_INT]) / g
    limit = P[P_LIMIT]
    if abs(cmd) > limit:  # anti-windup: hold the integral where the surface saturates
        cmd = math.copysign(limit, cmd)
        S[S_INT] -= e * dt
    return cmd


def spiral_command(P, S, H, R, t, x):  # noqa: ANN001, ANN201
    """Spiral (ITTC 2.2.5): direct — each deflection of the targets held until the rate is
    steady; reverse — a yaw-rate autopilot holds each target rate. A row of ``R`` per step:
    mean deflection, rate, speed, settled (1/0), target, time held."""
    k = int(S[S_K])
    target = P[P_TARGETS + k]
    cmd = target if P[P_REVERSE] == 0.0 else rate_pilot(P, S, target, x)
    if _record(P, S, H, t, x, cmd):
        j = int(S[S_NROWS])
        R[j, 0], R[j, 1], R[j, 2], R[j, 3] = S[S_LD], S[S_LR], S[S_LU], S[S_LOK]
        R[j, 4], R[j, 5] = target, t - S[S_START]
        S[S_NROWS] = j + 1
        S[S_K] = k + 1
        _reset(S, t)
        if k + 1 >= int(P[P_NT]):
            S[S_DONE] = 1.0
    return cmd


def pull_out_command(P, S, H, R, t, x):  # noqa: ANN001, ANN201
    """Pull-out (ITTC 2.2.6): a steady turn at +A, the surface to zero until the rate is steady
    (the residual), back to a straight course (the rate autopilot to 0, skipped when already
    straight), a steady turn at −A and its release. A row of ``R`` per side: deflection, rate
    before the release, release time, turn settled, residual rate, decay settled, and the rows
    of ``H`` the decay spans (first, end)."""
    phase = int(S[S_PHASE])
    if phase == 0:
        cmd = P[P_A]
    elif phase == 3:
        cmd = -P[P_A]
    elif phase == 2:
        cmd = rate_pilot(P, S, 0.0, x)
    else:
        cmd = 0.0
    if not _record(P, S, H, t, x, cmd):
        return cmd
    r, ok = S[S_LR], S[S_LOK]
    straight_tol = STEADY_DRIFT_ABS / scale_now(P, S, x)
    if phase == 0 or phase == 3:
        S[S_REL_D], S[S_REL_R], S[S_REL_T], S[S_REL_OK] = cmd, r, t, ok
    elif phase == 1 or phase == 4:
        j = int(S[S_NROWS])
        R[j, 0], R[j, 1], R[j, 2], R[j, 3] = S[S_REL_D], S[S_REL_R], S[S_REL_T], S[S_REL_OK]
        R[j, 4], R[j, 5], R[j, 6], R[j, 7] = r, ok, S[S_H0], S[S_NH]
        S[S_NROWS] = j + 1
    else:
        S[S_STRAIGHT] = 1.0 if (ok > 0 and abs(r) <= straight_tol) else 0.0
    phase += 1
    if phase == 2 and abs(r) <= straight_tol and ok > 0:
        phase = 3  # already straight: no autopilot needed
        S[S_STRAIGHT] = 1.0
    S[S_PHASE] = phase
    if phase >= PULL_OUT_PHASES:
        S[S_DONE] = 1.0
    else:
        _execute(S, t)
    _reset(S, t)
    return cmd


def depth_change_command(P, S, t, x):  # noqa: ANN001, ANN201
    """Open-loop depth change: planes at A (the diving sense) until the depth has changed by M,
    to −A until the pitch is back at its original value, then to zero (phase 2; the hold may
    hold the pitch instead); the end a quarter of the time after the depth's peak."""
    sense = S[S_SENSE]
    dz = sense * (x[2] - S[S_X0 + 2])
    phase = S[S_PHASE]
    if phase == 0.0 and dz >= abs(P[P_DEPTH]):
        S[S_PHASE] = 1.0
        S[S_CMD] = -S[S_CMD]
        _execute(S, t)
    elif phase == 1.0 and sense * (x[4] - S[S_X0 + 4]) >= 0.0:
        # pitch back to its original value (diving pitched the nose down: θ − θ0 < 0 until now)
        S[S_PHASE] = 2.0
        S[S_CMD] = 0.0
        _execute(S, t)
    elif phase == 2.0:
        if math.isnan(S[S_PEAK]) and dz < S[S_PREV]:
            S[S_PEAK] = t
        peak = S[S_PEAK]
        if not math.isnan(peak) and t >= peak + 0.25 * (peak - _last_execute(S)) + 1e-9:
            S[S_DONE] = 1.0
    S[S_PREV] = dz
    return S[S_CMD]


def depth_pilot_command(P, S, t, x):  # noqa: ANN001, ANN201
    """Closed-loop depth change's clock (the planes are set by :func:`depth_pitch`): executes at
    0, the first time the depth is reached, and the time it settled (within the band, staying
    there :data:`DEPTH_SETTLE` L/U)."""
    dz = S[S_SENSE] * (x[2] - S[S_X0 + 2])
    m = abs(P[P_DEPTH])
    if math.isnan(S[S_REACHED]) and dz >= m:
        S[S_REACHED] = t
        _execute(S, t)
    if not math.isnan(S[S_REACHED]) and abs(dz - m) <= S[S_BAND]:
        if math.isnan(S[S_INSIDE]):
            S[S_INSIDE] = t
        if t - S[S_INSIDE] >= DEPTH_SETTLE * P[P_SCALE]:
            _execute(S, S[S_INSIDE])
            S[S_DONE] = 1.0
    else:
        S[S_INSIDE] = math.nan
    return 0.0


def helm_command(P, S, H, R, t, x):  # noqa: ANN001, ANN201
    """The steering surface's command (rad) of the logic ``P`` at ``t`` (s, 0 at the execute)."""
    kind = int(P[P_KIND])
    if kind == TURN:
        return turn_command(P, S, H, t, x)
    if kind == ZIGZAG:
        return zigzag_command(P, S, t, x)
    if kind == SPIRAL:
        return spiral_command(P, S, H, R, t, x)
    if kind == PULL_OUT:
        return pull_out_command(P, S, H, R, t, x)
    if kind == DEPTH_CHANGE:
        return depth_change_command(P, S, t, x)
    return depth_pilot_command(P, S, t, x)


# ---------------------------------------------------------------------------------- the hold
def keeper_init(K, plane, rudder, steering, lim_plane, lim_rudder, length, x0):  # noqa: ANN001, ANN201
    """The hold of depth and pitch by the surface ``plane`` and of heading by ``rudder`` (−1:
    none) at the depth and heading of ``x0``; ``length`` L (m; 0: none); limits in rad."""
    for i in range(K.shape[0]):
        K[i] = 0.0
    K[K_PLANE], K[K_RUDDER], K[K_STEER] = plane, rudder, steering
    K[K_Z0], K[K_PSI0] = x0[2], x0[5]
    K[K_NEXT] = -math.inf
    K[K_TRIM] = math.nan
    K[K_LEN], K[K_LIMP], K[K_LIMR] = length, lim_plane, lim_rudder
    K[K_ON] = 1.0 if (plane >= 0 or rudder >= 0) else 0.0
    for j in range(3):
        o = K_PID + K_PIDW * j
        K[o + 3], K[o + 4] = -math.inf, math.inf
        K[o + 7] = math.nan


def keeper_due(K, t):  # noqa: ANN001, ANN201
    """True when the hold probes the surfaces' effect again at ``t`` (s)."""
    return K[K_ON] > 0 and t >= K[K_NEXT]


def _set_pid(K, j, kp, ki, kd, lo, hi, angle):  # noqa: ANN001, ANN202
    o = K_PID + K_PIDW * j
    K[o], K[o + 1], K[o + 2], K[o + 3], K[o + 4], K[o + 5] = kp, ki, kd, lo, hi, angle


def keeper_tune(K, t, x, g_q, g_r):  # noqa: ANN001, ANN201
    """Gain scheduling at ``t`` (s): the pitch and heading PIDs with natural frequency U/L,
    critically damped, their output an angular acceleration (rad/s²) that ``g_q`` = ∂q̇/∂δ
    (``g_r`` = ∂ṙ/∂δ, 1/s² per rad, probed now) turns into a deflection; the depth PID gives the
    pitch set-point with the time constant 5 L/U (ż ≈ −U θ), within ±:data:`HOLD_MAX_PITCH`."""
    speed = math.sqrt(x[6] ** 2 + x[7] ** 2 + x[8] ** 2)
    K[K_NEXT] = t + HOLD_PERIOD
    if speed < HOLD_MIN_SPEED:
        K[K_GQ] = 0.0
        K[K_GR] = 0.0
        return
    scale = K[K_LEN] / speed if K[K_LEN] > 0 else 1.0
    w = 1.0 / scale
    if K[K_PLANE] >= 0:
        K[K_GQ] = g_q
        top = K[K_LIMP] * abs(g_q)
        kz = 1.0 / (5.0 * scale * speed)  # rad per m: ż ≈ −U θ closes with time constant 5 L/U
        K[K_KZ] = kz
        _set_pid(K, 0, kz, kz / (20.0 * scale), 0.0, -HOLD_MAX_PITCH, HOLD_MAX_PITCH, 0.0)
        _set_pid(K, 1, w * w, 0.1 * w**3, 2.0 * w, -top, top, 1.0)
    if K[K_RUDDER] >= 0:
        K[K_GR] = g_r
        top = K[K_LIMR] * abs(g_r)
        _set_pid(K, 2, w * w, 0.1 * w**3, 2.0 * w, -top, top, 1.0)


def _pid(K, j, measurement, setpoint, dt, rate):  # noqa: ANN001, ANN202
    o = K_PID + K_PIDW * j
    e = measurement - setpoint
    if K[o + 5] > 0:
        e = wrap_angle(e)
    out, integral = pid_law(K[o], K[o + 1], K[o + 2], K[o + 3], K[o + 4], K[o + 6], e, rate, dt)
    K[o + 6] = integral
    K[o + 7] = measurement
    return out


def keeper_settled(K, x):  # noqa: ANN001, ANN201
    """True when the held depth and heading are within :data:`HOLD_TOLERANCE` (m, rad) of their
    set-points (the approach is steady only then)."""
    depth_ok = K[K_PLANE] < 0 or abs(x[2] - K[K_Z0]) <= HOLD_TOLERANCE
    heading_ok = K[K_RUDDER] < 0 or abs(wrap_angle(x[5] - K[K_PSI0])) <= HOLD_TOLERANCE
    return depth_ok and heading_ok


def keeper_command(K, x, dt, cmd, approach):  # noqa: ANN001, ANN201
    """Set the holding surfaces' commands in ``cmd`` (rad) for the state ``x``: depth → pitch →
    planes, heading → rudder (the steering surface only during the approach)."""
    zdot, _, thetadot, psidot = _euler_rates(x[3], x[4], x[6], x[7], x[8], x[9], x[10], x[11])
    plane, rudder, steer = int(K[K_PLANE]), int(K[K_RUDDER]), int(K[K_STEER])
    if plane >= 0 and (approach or plane != steer):
        if K[K_GQ] != 0.0:
            theta_d = _pid(K, 0, -x[2], -K[K_Z0], dt, -zdot)
            qdot = _pid(K, 1, x[4], theta_d, dt, thetadot)
            cmd[plane] = qdot / K[K_GQ]
        else:
            cmd[plane] = 0.0
    if rudder >= 0 and (approach or rudder != steer):
        if K[K_GR] != 0.0:
            rdot = _pid(K, 2, x[5], K[K_PSI0], dt, psidot)
            cmd[rudder] = rdot / K[K_GR]
        else:
            cmd[rudder] = 0.0


def pitch_hold(K, x, dt, theta):  # noqa: ANN001, ANN201
    """The plane command (rad) that holds the pitch ``theta`` (rad): an open-loop depth change's
    last phase, where a pitch-unstable vehicle cannot fly with its planes at zero."""
    if K[K_PLANE] < 0 or K[K_GQ] == 0.0:
        return 0.0
    thetadot = _euler_rates(x[3], x[4], x[6], x[7], x[8], x[9], x[10], x[11])[2]
    return _pid(K, 1, x[4], theta, dt, thetadot) / K[K_GQ]


def depth_pitch(K, x, dt, z_d, max_pitch):  # noqa: ANN001, ANN201
    """The plane command (rad) that flies to the depth ``z_d`` (m): the pitch set-point
    θ_d = trim + clip(k (z − z_d), ±``max_pitch``) of :func:`hydrokit.model.control.depth_to_pitch`
    (k = 1/(5 L) rad/m), clipped to ±``max_pitch``, held by the pitch PID."""
    if K[K_PLANE] < 0 or K[K_GQ] == 0.0:
        return 0.0
    trim = 0.0 if math.isnan(K[K_TRIM]) else K[K_TRIM]
    theta_d = min(max(trim + depth_to_pitch(x[2], z_d, K[K_KZ], max_pitch), -max_pitch), max_pitch)
    thetadot = _euler_rates(x[3], x[4], x[6], x[7], x[8], x[9], x[10], x[11])[2]
    return _pid(K, 1, x[4], theta_d, dt, thetadot) / K[K_GQ]


def manoeuvre_command(P, S, H, R, K, t, x, dt, cmd, surface):  # noqa: ANN001, ANN201
    """Every surface's command (rad) in ``cmd`` at ``t`` (s, 0 at the execute) after the execute:
    the logic's on the steering ``surface``, the hold's on the others (its probe, when due, is
    done before by the caller), the hold's pitch loop on the planes of a depth change where it
    flies them."""
    cmd[surface] = helm_command(P, S, H, R, t, x)
    if K[K_ON] > 0:
        keeper_command(K, x, dt, cmd, False)
        kind = int(P[P_KIND])
        if kind == DEPTH_CHANGE and S[S_PHASE] == 2.0 and int(K[K_PLANE]) == surface:
            cmd[surface] = pitch_hold(K, x, dt, S[S_X0 + 4])
        elif kind == DEPTH_PILOT:
            a = abs(P[P_A])
            cmd[surface] = min(max(depth_pitch(K, x, dt, S[S_X0 + 2] + P[P_DEPTH], P[P_MAXPITCH]), -a), a)


def approach_steady(rows, n, window, x):  # noqa: ANN001, ANN201
    """True when the velocities of the last ``window`` of the ``n`` states in ``rows`` vary by at
    most 1e-4 of the speed (m/s) and 1e-5 rad/s: the approach is steady."""
    speed = max(math.hypot(x[6], x[7]), 1e-3)
    for j in range(6, 12):
        lo = hi = rows[n - window, j]
        for i in range(n - window + 1, n):
            v = rows[i, j]
            lo, hi = min(lo, v), max(hi, v)
        if hi - lo > (1e-4 * speed if j < 9 else 1e-5):
            return False
    return True
