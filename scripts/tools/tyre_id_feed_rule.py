#!/usr/bin/env python3
"""The feed's taint and refresh (docs/MONITOR.md section 7): when the tyre identifier's curve
may not be fed to the friction estimator, in Python, the rule src/host/replay_real.c runs
(tyre_feed_taint before each sample's friction step, tyre_feed_refresh after its identifier
step) with the replay keys tid_feed_refresh (s; 0: off) and tid_feed_outlier_k.

A sample taints the identifier's curve when it is
  held:        |ax| > tid_feed_ax_max (when positive): under braking or driving the
               identifier's lateral-only model learns the combined slip's curve (TYRE_ID.md
               section 14), and after the braking that curve would be fed;
  implausible: |ay - ay_p| > tid_feed_outlier_k * tid_sd_ay, ay_p the lateral acceleration
               (F_f cos(delta) + F_r) / m of the identifier's last estimate (when its last
               step updated): a jump of ay that no tyre force follows within a sample, which
               the identifier's weights nevertheless take.
After a taint no curve is fed until the identifier has updated on tid_feed_refresh seconds
(summed) of untainted samples with |ay| >= tid_feed_outlier_k * tid_sd_ay, i.e. with lateral
force to learn the curve from, and then the first curve is fed only at a sample with |ay| <
tid_feed_outlier_k * tid_sd_ay: a curve changed where the tyres carry little lateral force
moves the friction estimator's lateral rows least, at the limit it moves its mu (MONITOR.md
section 7: the double run's loss without this). On the first implausible sample of a taint the friction
estimator's model error is set back to the parameter set's r_model_rel before that sample's
step: the fed curve's uncertainty joined to it (TYRE_ID.md section 14) would otherwise hide
the sample from the estimator's model-validity monitor.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass
class FeedTaint:
    """The taint state of one run; refresh > 0 (the rule off otherwise)."""
    refresh: float          # tid_feed_refresh [s]
    outlier_k: float = 5.0  # tid_feed_outlier_k [1]
    sd_ay: float = 0.2      # tid_sd_ay [m/s^2]
    ax_max: float = 0.5     # tid_feed_ax_max [m/s^2]; 0: no hold
    fresh: float = 0.0      # untainted excited time since the last taint [s]
    t_prev: float | None = None
    tainted: bool = False
    bad: bool = False       # this sample held or implausible
    ref_ok: bool = False    # the identifier's last step updated: its estimate predicts ay
    resume: bool = False    # the taint lifted, no curve fed since: the next at a low |ay|

    def before(self, ay: float, ax: float, ay_p: float) -> bool:
        """The sample (its ay, ax and the identifier's last estimate's ay_p) before the
        friction step; True when the model error is to be set back (the first implausible
        sample of a taint)."""
        held = self.ax_max > 0.0 and abs(ax) > self.ax_max
        implausible = (self.ref_ok and self.outlier_k > 0.0
                       and abs(ay - ay_p) > self.outlier_k * self.sd_ay)
        first = implausible and not self.tainted
        self.bad = held or implausible
        if self.bad:
            self.tainted = True
            self.fresh = 0.0
        return first

    def after(self, t: float, ay: float, updated: bool) -> None:
        """The sample at time t after the identifier's step (updated: its UPDATED flag)."""
        dt = t - self.t_prev if self.t_prev is not None else 0.0
        self.t_prev = t
        self.ref_ok = updated
        if self.tainted and not self.bad and updated and abs(ay) >= self.outlier_k * self.sd_ay:
            self.fresh += dt
            self.tainted = self.fresh < self.refresh
            self.resume = not self.tainted

    def may_feed(self, ay: float) -> bool:
        """Whether the feed's other conditions (TYRE_ID.md section 14) may feed this sample
        (its ay), after after()."""
        calm = not self.resume or abs(ay) < self.outlier_k * self.sd_ay
        return not self.tainted and calm

    def fed(self) -> None:
        """A curve was fed (the estimator took it): the resumption is over."""
        self.resume = False
