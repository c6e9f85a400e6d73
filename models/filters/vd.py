"""Variable dimension (VD) filter (Bar-Shalom & Birmiwal 1982 = seed 002 ref. [1], Fig. 2).

Normally the two-state Kalman filter (:class:`~axir.models.filters.kalman.KalmanCV`, seed 002
eqs. 1-10) tracks, and the fading-memory detector (eqs. 11-15) watches its innovations. When
L(k) > I1 the filter switches to the three-state (position, velocity, acceleration) model
(:class:`~axir.models.filters.kalman.KalmanCA`, white jerk of density σj²/(1 s),
``cfg.sigma_j`` = Tracker ``filter_sigma_j``), re-initialised M samples back (the detector's
effective window, eq. 15) and re-run over the stored measurements up to k:

- at j = k − M, from the two-state estimate at j − 1 and the measurement z(j) (interval T_j):
  â(j) = 2/T_j² · [z(j) − ẑ(j|j−1)], r̂(j) = z(j), v̂(j) = v̂(j−1|j−1) + T_j·â(j)
  (Bar-Shalom & Birmiwal 1982; Bar-Shalom, Li & Kirubarajan 2001 §11.6.2), and its covariance
  propagated exactly through this linear map from cov(z(j)) = r_j and P(j−1|j−1)
  (no process noise over that interval: the acceleration replaces it);
- then the three-state filter processes z(j + 1) … z(k).

While in the three-state mode the acceleration significance â²/P_aa is summed over a sliding
window of the last M updates; when the sum falls below I2 (χ²_M, scipy) the acceleration is no
longer significant and the filter returns to the two-state model with the three-state position
and velocity (and their 2×2 covariance); L restarts from 0. The maneuver flag is the mode.
The VD keeps this end test whatever ``cfg.fmd_end`` says (the hysteresis reading of I2 is the
SVD paper's detector, not Bar-Shalom & Birmiwal's). If fewer than M + 1 updates of the
two-state filter are stored (a detection right after the initialisation) the re-initialisation
uses the oldest stored one.
"""

from __future__ import annotations

from collections import deque

from .base import AxisFilter, Vec3
from .kalman import KalmanCA, KalmanCV


class VDFilter(AxisFilter):
    """VD filter: two-state Kalman + FMD, switching to a three-state Kalman on detection.

    State: ``cv`` (two-state filter, whose detector is this filter's), ``ca`` (three-state),
    ``mode`` (2 or 3), ``history``: the last M + 1 updates of the two-state filter as
    (z, T, T_all, r, s, pos, vel, p11, p12, p22): T the last prediction interval and pos … p22
    the state it started from (after any coasts), T_all the time since the previous update,
    ``switches``
    (number of mode changes, for diagnostics).
    """

    kind = "vd"
    has_acceleration = True

    def reset(self) -> None:
        self.cv = KalmanCV(self.cfg)
        self.fmd = self.cv.fmd
        self.ca = KalmanCA(self.cfg)
        self.mode = 2
        self.history: deque[tuple[float, ...]] = deque(maxlen=self.fmd.window + 1)
        self.since = 0.0  # time coasted since the last update [s]
        self.switches = 0

    @property
    def n(self) -> int:
        return self.cv.n

    def update(self, z: float, T: float, r: float | None = None, s: float = 1.0) -> float:
        cv = self.cv
        r = cv.r_default if r is None else r
        T_all = T + self.since  # interval since the previous update (coasts included)
        self.since = 0.0
        if self.mode == 3:
            ca = self.ca
            ca.predict_step(T, s)
            nu = ca.correct(z, r)
            cv.n += 1
            self.fmd.acceleration(ca.acc * ca.acc / ca.p33 if ca.p33 > 0.0 else 0.0)
            fmd = self.fmd
            acc_sum = fmd.A
            if len(fmd.acc) >= fmd.window and acc_sum < fmd.i2:
                self._to_two_state()
            return nu
        if cv.n < 2:
            return cv.update(z, T, r, s)
        before = (z, T, T_all, r, s, cv.pos, cv.vel, cv.p11, cv.p12, cv.p22)
        nu = cv._step(z, T, r, s)
        cv.n += 1
        self.history.append(before)
        stat = self.fmd.L
        if stat > self.fmd.i1:
            self._to_three_state()
        return nu

    def _to_three_state(self) -> None:
        """Switch on detection: re-initialise the three-state filter M samples back and re-run
        it over the stored measurements (module docstring)."""
        hist = list(self.history)
        z, T, _, r, _, pos, vel, p11, p12, p22 = hist[0]
        # linear map (z(j), r̂(j−1), v̂(j−1)) -> (r̂, v̂, â) at j; cov blockdiag(r, P(j−1|j−1))
        a0 = 2.0 / (T * T)
        rows = ((1.0, 0.0, 0.0), (2.0 / T, -2.0 / T, -1.0), (a0, -a0, -2.0 / T))
        cov_in = ((r, 0.0, 0.0), (0.0, p11, p12), (0.0, p12, p22))
        m = [[sum(rows[i][k] * cov_in[k][j] for k in range(3)) for j in range(3)]
             for i in range(3)]
        P = [[sum(m[i][k] * rows[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
        acc = a0 * (z - (pos + T * vel))  # â = 2/T² [z(j) − ẑ(j|j−1)]
        self.ca.set(z, vel + T * acc, acc, (P[0][0], P[0][1], P[0][2], P[1][1], P[1][2],
                                            P[2][2]))
        for z_j, _, T_j, r_j, s_j, *_ in hist[1:]:
            self.ca.predict_step(T_j, s_j)
            self.ca.correct(z_j, r_j)
        self.mode = 3
        self.switches += 1
        self.history.clear()
        fmd = self.fmd
        fmd.L = 0.0
        fmd.acc.clear()
        fmd.A = 0.0
        fmd.flag = True

    def _to_two_state(self) -> None:
        """Back to the two-state model with the three-state position, velocity, covariance."""
        ca, cv = self.ca, self.cv
        cv.pos, cv.vel = ca.pos, ca.vel
        cv.p11, cv.p12, cv.p22 = ca.p11, ca.p12, ca.p22
        self.mode = 2
        self.switches += 1
        fmd = self.fmd
        fmd.L = 0.0
        fmd.acc.clear()
        fmd.A = 0.0
        fmd.flag = False

    def coast(self, T: float, s: float = 1.0) -> None:
        if self.mode == 3:
            self.ca.predict_step(T, s)
        else:
            self.cv.coast(T, s)
        if self.cv.n >= 2:
            self.since += T

    # ------------------------------------------------------------------ outputs
    @property
    def x(self) -> Vec3:
        if self.mode == 3:
            return self.ca.pos, self.ca.vel, self.ca.acc
        return self.cv.x

    @property
    def P(self) -> Vec3:
        if self.mode == 3:
            return self.ca.p11, self.ca.p12, self.ca.p22
        return self.cv.P

    def predict(self, T: float) -> Vec3:
        if self.mode == 3:
            return self.ca.extrapolate(T)
        return self.cv.predict(T)
