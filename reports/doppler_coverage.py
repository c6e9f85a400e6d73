"""Doppler coverage of acquisition over the PRI schedule (issue 11, docs/doppler_coverage.md).

For radial speeds −1000 … +1000 m/s (Doppler −2ṙ/λ) computes, from the manager's default
parameters and the filter formula (:func:`axir.models.manager.doppler_search.loss_db`, the
generator's one-pole resonators):

- the loss against a filter-centred target with the three filters at one position (before
  issue 11) at PRI 1;
- the loss with the manager's Doppler steps at each PRI, the best PRI (acquisition cycles the
  PRIs) and the worst (tentative needs all three);
- the blind speeds: Doppler folded into the clutter notch (``clutter_notch_speed``) at every PRI
  at once, and the tentative rejection zone (unfolded candidates within the notch, tolerance
  ``doppler_tol_fraction``);
- with ``TargetGenerator.mti = 1`` the canceller's relative gain 2·sin²(π·f·PRI) (SNR against
  white noise) added to the loss, best PRI.

Writes ``docs/img/doppler_coverage.png`` and prints the markdown table of
docs/doppler_coverage.md. Usage: ``.venv/bin/python reports/doppler_coverage.py`` (≈ 2 s).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from axir.models.manager import RadarManager
from axir.models.manager.ambiguity import pri_seconds
from axir.models.manager.doppler_search import coverage_steps, fold_cycles, loss_db

ROOT = Path(__file__).resolve().parents[1]


def coverage(v_max: float = 1000.0, n: int = 20001) -> dict[str, np.ndarray | float]:
    """Loss curves [dB] and blind-speed masks over radial speeds [m/s] (module docstring)."""
    m = RadarManager()
    lam, s, pole = m.wavelength, m.doppler_spacing_fraction, m.doppler_pole
    v = np.linspace(-v_max, v_max, n)
    f = -2.0 * v / lam
    pris = [pri_seconds(k) for k in (m.pri1_bins, m.pri2_bins, m.pri3_bins)]
    n_steps = coverage_steps(s, pole, m.doppler_max_loss_db)
    base = m.doppler_search_centre
    single = loss_db(f, 1.0 / pris[0], base, 1, s, pole)
    per_pri = np.array([loss_db(f, 1.0 / p, base, n_steps, s, pole) for p in pris])
    notch = 2.0 * m.clutter_notch_speed / lam
    in_notch = np.array([fold_cycles(f, 1.0 / p) / p < notch for p in pris])
    blind_all = in_notch.all(axis=0)
    # tentative rejection: a candidate within the notch survives the three PRIs when every
    # folded Doppler is within notch + tolerance of 0
    reject = np.array([fold_cycles(f, 1.0 / p) / p < notch + m.doppler_tol_fraction / p
                       for p in pris]).all(axis=0)
    mti = np.array([-10.0 * np.log10(np.maximum(2.0 * np.sin(np.pi * f * p) ** 2, 1e-30))
                    for p in pris])
    return {"v": v, "single": single, "per_pri": per_pri, "best": per_pri.min(axis=0),
            "worst": per_pri.max(axis=0), "blind_all": blind_all, "reject": reject,
            "mti_best": (per_pri + mti).min(axis=0), "n_steps": float(n_steps),
            "pri_bins": (m.pri1_bins, m.pri2_bins, m.pri3_bins)}


def table(c: dict) -> str:
    """Markdown summary of :func:`coverage`."""
    v = c["v"]
    ok = ~(c["blind_all"] | c["reject"])
    rows = [
        ("one filter position, PRI 1 (before)", c["single"], np.ones_like(ok)),
        (f"{int(c['n_steps'])} Doppler steps, worst PRI (tentative)", c["worst"], ok),
        (f"{int(c['n_steps'])} Doppler steps, best PRI (acquisition)", c["best"], ok),
        ("same with the canceller on (below 4.5°), best PRI", c["mti_best"], ok),
    ]
    out = ["| filter bank | worst loss [dB] | speeds within 3 dB | within 4 dB |",
           "|---|---|---|---|"]
    for name, loss, mask in rows:
        lv = loss[mask]
        out.append(f"| {name} | {lv.max():.2f} | {np.mean(lv <= 3.0):.1%} | "
                   f"{np.mean(lv <= 4.0):.1%} |")
    dv = v[1] - v[0]
    out.append("")
    out.append(f"Blind speeds (folded into the {RadarManager().clutter_notch_speed:g} m/s clutter "
               f"notch at every PRI at once): {np.mean(c['blind_all']):.2%} of the band "
               f"({c['blind_all'].sum() * dv:.0f} m/s); tentative rejection zone (unfolded "
               f"candidates reaching the notch, aliases one PRF apart included): "
               f"{np.mean(c['reject']):.2%}; together "
               f"{np.mean(c['blind_all'] | c['reject']):.2%}.")
    return "\n".join(out)


def plot(c: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = c["v"]
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(10, 7.5), sharex=True)
    ax.plot(v, c["single"], color="0.7", lw=0.6, label="one filter position, PRI 1 (before)")
    ax.plot(v, c["worst"], color="C1", lw=0.8,
            label=f"{int(c['n_steps'])} Doppler steps, worst of 3 PRIs")
    ax.plot(v, c["best"], color="C0", lw=0.8,
            label=f"{int(c['n_steps'])} Doppler steps, best of 3 PRIs")
    blind = c["blind_all"] | c["reject"]
    for a in (ax, ax2):
        a.fill_between(v, 0, 25, where=blind, color="C3", alpha=0.3, lw=0,
                       label="blind / clutter-notch rejection")
        a.axhline(4.0, color="k", ls="--", lw=0.8, label="goal 4 dB")
        a.set_ylabel("loss vs filter-centred target [dB]")
        a.set_ylim(25, 0)
        a.set_xlim(v[0], v[-1])
    ax.legend(loc="lower right", fontsize=8)
    pris = "/".join(str(int(k)) for k in c["pri_bins"])
    ax.set_title(f"Acquisition Doppler coverage, default RadarManager (PRIs {pris} bins), "
                 "canceller off (antenna above 4.5°)")
    ok = ~blind
    ax2.plot(v, c["mti_best"], color="C2", lw=0.8,
             label=f"{int(c['n_steps'])} Doppler steps + two-pulse canceller, best of 3 PRIs "
                   f"(> 4 dB for {np.mean(c['mti_best'][ok] > 4.0):.1%} of the speeds)")
    ax2.set_title("Main-beam clutter (antenna below 4.5°): the canceller's notch 2·sin²(πf·PRI) "
                  "added (white-noise SNR)")
    ax2.set_xlabel("radial speed [m/s] (> 0 receding)")
    ax2.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--png", type=Path, default=ROOT / "docs" / "img" / "doppler_coverage.png")
    args = ap.parse_args()
    c = coverage()
    plot(c, args.png)
    print(table(c))


if __name__ == "__main__":
    main()
