"""α-β (g-h) filters of the AXIR digital tracker, evolutive and steady gains, maneuver check.

Sources
-------
- seed 000 "Alpha-Beta Filters": one α-β filter per Cartesian axis (X, Y, Z), DSP form
  ("Beginning period": P = V3 + V5, V1 = In − P, V2 = Alpha·V1, V4 = Beta·V1, OutP = P + V2,
  OutV = V4 + V5, V3 = OutP, V5 = OutV), with the update rules
  Xp(k+1) = X(k) + T·V(k), X(k+1) = Xp + α (z − Xp), V(k+1) = V(k) + (β/T)(z − Xp).
  In the DSP listing V5 is the velocity expressed per period; here it is in m/s, so the
  prediction is written P = V3 + V5·T with T = dt (the actual step), and the velocity
  correction divides the error by T as the seed says ("we have just to divide the error by the
  sampling period"). β is therefore dimensionless, as in the seed and in Kalata's papers.
- seed 000 "Evolutive coefficients": α(n) = 2(2n − 1)/(n(n + 1)), β(n) = 6/(n(n + 1)),
  n = 1, 2, … — exactly the recursive least-squares straight-line fit for uniform sampling
  (SYSTEM.md; filterpy ``least_squares_parameters(n − 1)``).
- Kalata, P. R. (1984), "The tracking index: a generalized parameter for α-β and α-β-γ target
  trackers", IEEE Trans. Aerospace and Electronic Systems AES-20(2), 174-182: steady-state
  α-β gains of the Kalman filter for the constant-velocity model with piecewise-constant
  (discrete white-noise) acceleration of standard deviation σ_w and position noise σ_n, as a
  function of the tracking index Λ = σ_w T²/σ_n.
- Brookner, E. (1998), "Tracking and Kalman Filtering Made Easy", Wiley, eq. (1.2-19): variance
  reduction ratio of the one-step prediction of a g-h filter in white measurement noise,
  σ²(x̂ₙ₊₁,ₙ)/σ² = (2g² + 2h + gh)/(g(4 − 2g − h)).
- Bar-Shalom, Li & Kirubarajan (2001), "Estimation with Applications to Tracking and
  Navigation", §11.2: fading-memory average of the normalized innovation squared as maneuver
  detector, and its chi-square approximation.

Implementation note: the three axes are plain Python floats, not numpy arrays; measured on this
project's machine one 3-axis update costs ≈ 0.7 µs with floats vs ≈ 4.4 µs with numpy (3 is
far too small for vectorisation to pay off).
"""

from __future__ import annotations

import math

from scipy.stats import chi2

from .axisfilter import CVEstimate, FilterConfig
from .kalman import q_cwna

Vec3 = tuple[float, float, float]


# --------------------------------------------------------------------------------------------
# Gains
# --------------------------------------------------------------------------------------------
def evolutive_gains(n: int) -> tuple[float, float]:
    """Evolutive gains (α(n), β(n)) for the n-th measurement, n = 1, 2, … [1].

    # seed 000 "Evolutive coefficients": α(n) = 2(2n−1)/(n(n+1)), β(n) = 6/(n(n+1))
    """
    if n < 1:
        raise ValueError(f"evolutive_gains: n = {n} must be >= 1")
    den = n * (n + 1.0)
    return 2.0 * (2.0 * n - 1.0) / den, 6.0 / den


def tracking_index(sigma_accel: float, T: float, sigma_meas: float) -> float:
    """Kalata's tracking index Λ = σ_w T² / σ_n [1] (Kalata 1984).

    Args:
        sigma_accel: σ_w, standard deviation of the target acceleration (piecewise constant over
            a sample interval) [m/s²].
        T: sample interval [s].
        sigma_meas: σ_n, standard deviation of the position measurement noise [m].
    """
    if sigma_meas <= 0.0 or T <= 0.0 or sigma_accel < 0.0:
        raise ValueError("tracking_index: need sigma_meas > 0, T > 0, sigma_accel >= 0")
    return sigma_accel * T * T / sigma_meas


def kalata_gains(lam: float) -> tuple[float, float]:
    """Steady-state α-β gains (α, β) [1] for the tracking index Λ = ``lam`` (Kalata 1984).

    Kalata's closed form, α = −(Λ² + 8Λ − (Λ + 4)√(Λ² + 8Λ))/8,
    β = (Λ² + 4Λ − Λ√(Λ² + 8Λ))/4, is evaluated through the damping parameter
    r = √(1 − α) = (4 + Λ − √(Λ² + 8Λ))/4 (root of 2r² − (4 + Λ)r + 2 = 0), computed as
    r = 4/(4 + Λ + √(Λ² + 8Λ)) to avoid cancellation for small Λ; then
    α = 1 − r², β = 2(1 − r)². These satisfy Kalata's relations Λ² = β²/(1 − α) and
    β = 2(2 − α) − 4√(1 − α) (the Kalman steady state of the discrete white-noise acceleration
    model; note they are *not* the Benedict-Bordner pair β = α²/(2 − α), which minimises a
    different criterion — the two differ by a few percent).
    """
    if not (lam >= 0.0 and math.isfinite(lam)):
        raise ValueError(f"kalata_gains: tracking index {lam!r} must be finite and >= 0")
    s = math.sqrt(lam * lam + 8.0 * lam)
    one_minus_r = (lam + s) / (4.0 + lam + s)
    r = 1.0 - one_minus_r
    return one_minus_r * (1.0 + r), 2.0 * one_minus_r * one_minus_r


def prediction_vrr(alpha: float, beta: float) -> float:
    """One-step prediction variance reduction ratio of a steady α-β filter [1].

    σ²(pred)/σ² = (2α² + 2β + αβ)/(α(4 − 2α − β)) for white measurement noise of variance σ²
    and no target maneuver (Brookner 1998, eq. 1.2-19). Infinite outside the stability region
    0 < α < 2, 0 < β < 4 − 2α.
    """
    den = alpha * (4.0 - 2.0 * alpha - beta)
    if alpha <= 0.0 or beta <= 0.0 or den <= 0.0:
        return math.inf
    return (2.0 * alpha * alpha + 2.0 * beta + alpha * beta) / den


def stable_gains(alpha: float, beta: float) -> bool:
    """True when (α, β) are finite and inside the α-β stability triangle (Kalata 1984)."""
    return (
        math.isfinite(alpha) and math.isfinite(beta)
        and 0.0 < alpha < 2.0 and 0.0 < beta < 4.0 - 2.0 * alpha
    )


def scheduled_gains(n: int, n_max: int, alpha_ss: float, beta_ss: float
                    ) -> tuple[float, float, bool]:
    """(α, β, evolutive) for the n-th measurement: max(evolutive, steady) per gain.

    The evolutive index is capped at ``n_max`` when 0 < n_max < n (a capped schedule is a
    fixed-gain filter, not evolutive); steady gains count only when :func:`stable_gains`.
    ``evolutive`` is True while both gains are the (uncapped) evolutive ones.
    """
    capped = 0 < n_max < n
    a, b = evolutive_gains(n_max if capped else n)
    evolutive = not capped
    if alpha_ss > 0.0 and stable_gains(alpha_ss, beta_ss):
        if alpha_ss >= a:
            a, evolutive = alpha_ss, False
        if beta_ss >= b:
            b, evolutive = beta_ss, False
    return a, b, evolutive


def innovation_factor(alpha: float, beta: float, evolutive: bool) -> float:
    """S/σ² of an α-β update with gains (α, β) [1].

    Evolutive (least-squares) phase: the LS gain is α(n) = P/(P + σ²) with P the prediction
    variance from n − 1 points, so S/σ² = 1/(1 − α(n)) (equal to 1 + 2(2m + 1)/(m(m − 1)),
    m = n − 1, the LS line-extrapolation variance); steady or mixed gains: 1 + VRR(α, β)
    (Brookner eq. 1.2-19). Infinite when undefined (n ≤ 2).
    """
    if evolutive:
        return 1.0 / (1.0 - alpha) if alpha < 1.0 else math.inf
    return 1.0 + prediction_vrr(alpha, beta)


# --------------------------------------------------------------------------------------------
# Filter
# --------------------------------------------------------------------------------------------
def ab_correct(x: float, v: float, z: float, T: float, a: float, bt: float
               ) -> tuple[float, float, float]:
    """One axis of the seed-000 α-β update: (x, v) predicted over T [s] and corrected by the
    measurement z with gains α = ``a`` and β/T = ``bt`` [1/s]; returns (x, v, ν).

    # seed 000 "Beginning period" (DSP form), P = V3 + V5·T with T = dt:
    #   P = V3 + V5·T; V1 = In − P; V2 = α·V1; V4 = (β/T)·V1;
    #   OutP = P + V2; OutV = V4 + V5; V3 = OutP; V5 = OutV
    """
    p = x + v * T  # P = V3 + V5·T
    v1 = z - p  # V1 = In − P
    return p + a * v1, v + bt * v1, v1  # OutP = P + α·V1, OutV = V5 + (β/T)·V1


class AlphaBeta3:
    """Three independent α-β filters (X, Y, Z) in the seed's DSP form.

    State: position ``x`` [m], velocity ``v`` [m/s] (3 floats each, lists), number of
    measurements used ``n`` (0 = not initialised), gains of the last update.

    Gain schedule: the n-th measurement uses the evolutive gains α(n), β(n) (seed 000) while
    they exceed the steady gains supplied by the manager, each gain separately:
    α = max(α(n), α_ss), β = max(β(n), β_ss). α(n), β(n) decrease monotonically, so once a steady
    gain is reached it takes over for good (unless the manager raises it again). A steady gain of
    0 (or an unstable pair) means "not supplied": evolutive gains only (growing-memory least
    squares). ``n_max`` > 0 caps the evolutive index (α(n) ≥ α(n_max)), 0 = no cap.

    With uniform T the evolutive phase reproduces the least-squares line fit of all
    measurements exactly (position and slope at the last sample), whatever the initial state,
    because α(1) = α(2) = 1 and β(2) = 1. At initialisation (n = 1) the velocity is set to 0.
    """

    def __init__(self, n_max: int = 0) -> None:
        self.n_max = int(n_max)
        self.reset()

    def reset(self) -> None:
        """Forget the track (n = 0)."""
        self.x: list[float] = [0.0, 0.0, 0.0]
        self.v: list[float] = [0.0, 0.0, 0.0]
        self.n = 0
        self.alpha = 1.0
        self.beta = 0.0
        self.evolutive = True

    @property
    def initialised(self) -> bool:
        return self.n > 0

    def initialise(self, z: Vec3) -> None:
        """Start the track on the first measurement ``z`` [m] (n = 1, velocity 0)."""
        self.x = [float(z[0]), float(z[1]), float(z[2])]
        self.v = [0.0, 0.0, 0.0]
        self.n = 1
        self.alpha, self.beta, self.evolutive = 1.0, 0.0, True

    def gains(self, n: int, alpha_ss: float = 0.0, beta_ss: float = 0.0) -> tuple[float, float]:
        """Gains (α, β) used for the n-th measurement given the manager's steady gains."""
        a, b, self.evolutive = scheduled_gains(n, self.n_max, alpha_ss, beta_ss)
        return a, b

    def update(self, z: Vec3, T: float, alpha_ss: float = 0.0, beta_ss: float = 0.0) -> Vec3:
        """Predict over T [s] then correct with the measurement z [m]; returns the innovations
        ν = z − P [m] per axis. Initialises on the first call (innovations 0).

        # seed 000 "Beginning period" (DSP form), P = V3 + V5·T with T = dt:
        #   P = V3 + V5·T; V1 = In − P; V2 = α·V1; V4 = (β/T)·V1;
        #   OutP = P + V2; OutV = V4 + V5; V3 = OutP; V5 = OutV
        """
        if self.n == 0:
            self.initialise(z)
            return 0.0, 0.0, 0.0
        a, b = self.gains(self.n + 1, alpha_ss, beta_ss)
        self.alpha, self.beta = a, b
        bt = b / T
        x, v = self.x, self.v
        nu = [0.0, 0.0, 0.0]
        for i in range(3):
            x[i], v[i], nu[i] = ab_correct(x[i], v[i], z[i], T, a, bt)
        self.n += 1
        return nu[0], nu[1], nu[2]

    def coast(self, T: float) -> None:
        """Advance the state by T [s] on prediction only (no measurement; n unchanged)."""
        x, v = self.x, self.v
        x[0] += v[0] * T
        x[1] += v[1] * T
        x[2] += v[2] * T

    def predict(self, T: float) -> Vec3:
        """Predicted position T [s] after the current state time [m] (state unchanged)."""
        x, v = self.x, self.v
        return x[0] + v[0] * T, x[1] + v[1] * T, x[2] + v[2] * T

    def innovation_factor(self) -> float:
        """S/σ² for the last update: innovation variance over measurement variance [1]
        (:func:`innovation_factor`)."""
        return innovation_factor(self.alpha, self.beta, self.evolutive)


class AlphaBetaAxis(CVEstimate):
    """One α-β axis behind the common :class:`~axir.models.axisfilter.AxisFilter` interface.

    Same equations and gain schedule as :class:`AlphaBeta3` (:func:`ab_correct`,
    :func:`scheduled_gains`; bit-identical per axis). Steady gains come from the radar manager
    (:meth:`set_steady_gains`) or, with ``cfg.auto_gains`` and none supplied, from Kalata's
    steady state for the tracking index Λ = (s·σm) T²/√r (a piecewise-constant-acceleration
    model, Kalata 1984; # assumption: σm of seed 002 eq. 4 used as Kalata's σ_w).

    Covariance ``P``: the error covariance of this fixed-gain filter for a target following the
    two-state model of seed 002 eq. (4) with σm, measured with variance r: P(k|k) =
    (I − KH)(ΦPΦᵀ + Q)(I − KH)ᵀ + K r Kᵀ, K = [α, β/T]ᵀ (Joseph form: valid for any gain). In
    the evolutive phase with σm = 0 it is the least-squares line-fit covariance
    (P_pp = α(n)·r). Detector: d = ν²/S with S = P_pp(k|k−1) + r.
    """

    kind = "alphabeta"

    def __init__(self, cfg: FilterConfig | None = None) -> None:
        super().__init__(cfg)
        #: run the per-axis detector (the Tracker's seed-000 configuration uses its 3-D
        #: detector instead and turns this off)
        self.detect = True

    def reset(self) -> None:
        self.n = 0
        self.pos = self.vel = 0.0
        self.p11 = self.p12 = self.p22 = 0.0
        self.alpha, self.beta, self.evolutive = 1.0, 0.0, True
        self.alpha_ss = self.beta_ss = 0.0
        self._steady: tuple[float, float] | None = None  # steady gains in use (fast path)
        self.fmd.reset()

    def set_steady_gains(self, alpha: float, beta: float) -> None:
        self.alpha_ss, self.beta_ss = alpha, beta

    def innovation_factor(self) -> float:
        """S/σ² of the last update from the gains alone (:func:`innovation_factor`) [1]."""
        return innovation_factor(self.alpha, self.beta, self.evolutive)

    def _predict_cov(self, T: float, s: float) -> tuple[float, float, float]:
        """ΦPΦᵀ + Q over T [s] (seed 002 eqs. 4, 7)."""
        sm = s * self.cfg.sigma_m
        q11, q12, q22 = q_cwna(sm * sm, T)  # seed 002 eq. (4)
        p12, p22 = self.p12, self.p22
        a = p12 + T * p22
        return self.p11 + T * (p12 + a) + q11, a + q12, p22 + q22

    def update(self, z: float, T: float, r: float | None = None, s: float = 1.0) -> float:
        if r is None:
            r = self.r_default
        n = self.n
        if n == 0:  # AlphaBeta3.initialise: x = z, v = 0, n = 1
            self.pos, self.vel, self.n = z, 0.0, 1
            self.alpha, self.beta, self.evolutive = 1.0, 0.0, True
            self.p11, self.p12, self.p22 = r, 0.0, 0.0
            return 0.0
        cfg = self.cfg
        a_ss, b_ss = self.alpha_ss, self.beta_ss
        if cfg.auto_gains and not stable_gains(a_ss, b_ss):
            a_ss, b_ss = kalata_gains(tracking_index(s * cfg.sigma_m, T, math.sqrt(r)))
        if self._steady == (a_ss, b_ss):
            # both steady gains already exceeded the evolutive ones; α(n), β(n) only decrease
            # with n (or are capped), so scheduled_gains would return them again
            a, b = a_ss, b_ss
        else:
            a, b, ev = scheduled_gains(n + 1, cfg.n_max, a_ss, b_ss)
            self.evolutive = ev
            self._steady = (a, b) if (a, b) == (a_ss, b_ss) else None
        self.alpha, self.beta = a, b
        bt = b / T
        self.pos, self.vel, nu = ab_correct(self.pos, self.vel, z, T, a, bt)
        # covariance of the fixed-gain filter, Joseph form (class docstring), after
        # ΦPΦᵀ + Q (seed 002 eqs. 4, 7)
        sm = s * cfg.sigma_m
        q11, q12, q22 = q_cwna(sm * sm, T)
        p12, p22 = self.p12, self.p22
        pa = p12 + T * p22
        pp11, pp12, pp22 = self.p11 + T * (p12 + pa) + q11, pa + q12, p22 + q22
        c = 1.0 - a
        self.p11 = c * c * pp11 + a * a * r
        self.p12 = c * (pp12 - bt * pp11) + a * bt * r
        self.p22 = pp22 - 2.0 * bt * pp12 + bt * bt * (pp11 + r)
        if n >= 2 and self.detect:
            fmd = self.fmd
            fmd.innovation(nu * nu / (pp11 + r))
            fmd.decide()
        self.n = n + 1
        return nu

    def coast(self, T: float, s: float = 1.0) -> None:
        if self.n > 0:
            self.pos += self.vel * T
            self.p11, self.p12, self.p22 = self._predict_cov(T, s)


# --------------------------------------------------------------------------------------------
# Maneuver detector
# --------------------------------------------------------------------------------------------
class ManeuverDetector:
    """Fading-memory normalized-innovation-squared maneuver detector (Bar-Shalom et al. §11.2).

    Choice: d(k) = ρ·d(k − 1) + q(k), q = νᵀS⁻¹ν with the 3-D innovation ν of the α-β
    filters and S its no-maneuver covariance. S is *model-based*, not a running estimate of the
    innovation variance (a running estimate would absorb the maneuver it should detect):
    S = f·R where R is the Cartesian measurement covariance from the declared measurement
    accuracies (σ_range in range, σ_angle × range across the beam) and f = 1 + VRR(α, β) the
    prediction factor of the gains in use (see :meth:`AlphaBeta3.innovation_factor`; the same
    gains on each axis make the prediction covariance proportional to R). Because the spherical
    unit vectors are orthonormal, q = ((u_ρ·ν)²/σ_ρ² + (u_θ·ν)²/(ρσ_a)² + (u_φ·ν)²/(ρσ_a)²)/f.

    Under no maneuver q has 3 degrees of freedom; (1 + ρ)·d is approximately χ² with
    3(1 + ρ)/(1 − ρ) degrees of freedom (moment matching of the fading sum of independent χ²₃
    terms). The flag is raised when d exceeds that quantile at 1 − P_fa. α-β innovations with
    non-optimal gains are mildly correlated, so P_fa is approximate.
    """

    def __init__(self, fading: float = 0.8, pfa: float = 1e-3) -> None:
        if not 0.0 <= fading < 1.0:
            raise ValueError(f"ManeuverDetector: fading = {fading!r} must be in [0, 1)")
        if not 0.0 < pfa < 1.0:
            raise ValueError(f"ManeuverDetector: pfa = {pfa!r} must be in (0, 1)")
        self.fading = float(fading)
        self.pfa = float(pfa)
        dof = 3.0 * (1.0 + fading) / (1.0 - fading)
        self.threshold = float(chi2.ppf(1.0 - pfa, dof)) / (1.0 + fading)
        self.reset()

    def reset(self) -> None:
        self.d = 0.0
        self.flag = False

    @staticmethod
    def nis(
        nu: Vec3, az: float, el: float, rho: float, sigma_range: float, sigma_angle: float,
        factor: float,
    ) -> float:
        """Normalized innovation squared q = νᵀS⁻¹ν [1] (see class docstring).

        Args:
            nu: innovation (X, Y, Z) [m]; az, el: direction of the measurement [rad];
            rho: range [m]; sigma_range [m], sigma_angle [rad]: measurement accuracies;
            factor: S/R prediction factor [1].
        """
        ca, sa, ce, se = math.cos(az), math.sin(az), math.cos(el), math.sin(el)
        nx, ny, nz = nu
        q_r = ce * sa * nx + ce * ca * ny + se * nz  # along u_ρ
        q_a = ca * nx - sa * ny  # along u_θ
        q_e = -se * sa * nx - se * ca * ny + ce * nz  # along u_φ
        sc2 = (rho * sigma_angle) ** 2
        return (q_r * q_r / (sigma_range * sigma_range) + (q_a * q_a + q_e * q_e) / sc2) / factor

    def update(self, q: float) -> bool:
        """Add one normalized innovation q; returns the maneuver flag."""
        if math.isfinite(q):
            self.d = self.fading * self.d + q
            self.flag = self.d > self.threshold
        return self.flag
