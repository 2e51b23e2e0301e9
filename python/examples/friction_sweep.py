"""K_II of a closed inclined crack against the friction coefficient, from Python.

The case is ``examples/inclined_crack_friction_2d.toml``: a square plate [-2, 2]² (E = 1,
ν = 0.3, plane strain) compressed by σ = 1 on its top and bottom edges, with a centre crack
of length 2a = 0.4 inclined at β = 45°, closed by the compression, and Coulomb friction μ
on its faces. This script runs it once per μ with the ``--set`` override of the friction,
reads K_II at both tips from the results, and plots K_II(μ) against the closed form for an
infinite plate. Run it from the repository root (after ``pip install ./python``)::

    python python/examples/friction_sweep.py            # writes out/friction_sweep/

The closed form. The far stress is σ∞ = diag(0, −σ). On the crack plane, with e1 along
the crack towards the tip and e2 its normal (the tip frame that fissure writes in
summary.json, docs/conventions.md), the faces are pressed together by p = −e2·σ∞·e2 =
σ cos²β and sheared by τ = e1·σ∞·e2 = −σ sinβ cosβ. A closed crack transmits the pressure;
friction carries at most μp of the shear. While |τ| > μp the faces slip and the shear
left to load the tips is τ − sign(τ) μp, so

    K_II = √(πa) (τ − sign(τ) μ p) = −σ √(πa) (sinβ cosβ − μ cos²β),

whose magnitude is the classical σ√(πa)(sinβcosβ − μcos²β). The sign is fissure's
convention (K_II > 0 when the lip on the e2 side slides along +e1): here that lip slides
down the slope, along −e1. When μ ≥ tanβ (= 1 at 45°) friction holds the faces stuck and
K_II = 0. (K_I = 0: the crack stays closed.)

The plate is finite (W/2a = 10), so its K_II is about 1% above the infinite-plate value
(0.2801 against 0.2774 at μ = 0.3, matching GetFEM on this plate); the check below allows
1.5% of the frictionless value σ√(πa) sinβ cosβ.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import fissure

REPO = Path(__file__).resolve().parents[2]
CASE = REPO / "examples" / "inclined_crack_friction_2d.toml"

#: The friction coefficients of the sweep (the slip/stick threshold tanβ = 1 is avoided:
#: there both answers are K_II = 0 and the status is a tie).
MUS = [0.0, 0.15, 0.3, 0.45, 0.6, 0.75, 0.9, 1.1]

#: Allowed difference to the closed form, as a fraction of σ√(πa) sinβ cosβ.
TOLERANCE = 0.015


def geometry(summary: dict) -> tuple:
    """(a, β) of the crack, from its two tips in the summary."""
    tips = [p["x"] for p in summary["steps"][-1]["cracks"][0]["front"]]
    dx, dy = tips[1][0] - tips[0][0], tips[1][1] - tips[0][1]
    return 0.5 * math.hypot(dx, dy), math.atan2(abs(dy), abs(dx))


def closed_form_kii(mu: float, e1, e2, sigma: float, a: float) -> float:
    """K_II of a closed crack under the far stress diag(0, −σ), in the tip frame (e1, e2)."""
    s = [[0.0, 0.0], [0.0, -sigma]]

    def proj(u, v):
        return sum(u[i] * s[i][j] * v[j] for i in range(2) for j in range(2))

    tau = proj(e1, e2)
    p = -proj(e2, e2)
    if p <= 0.0:
        raise ValueError("the crack is not pressed closed: the closed form does not apply")
    if abs(tau) <= mu * p:
        return 0.0  # stick: friction carries the whole shear
    return math.sqrt(math.pi * a) * (tau - math.copysign(mu * p, tau))


def sweep(mus, out: Path, sigma: float = 1.0) -> tuple:
    """Runs the case once per μ into out/friction=μ/. Returns the rows, one per run and
    tip: (μ, tip, K_I, K_II, closed form, slipping points, sticking points), and the
    crack's (a, β)."""
    rows = []
    a = beta = None
    for mu in mus:
        r = fissure.run(CASE, out=out / f"friction={mu}", overrides={"cracks.0.contact.friction": mu})
        sif = r.sif("inclined")
        last = sif[sif["step"] == r.steps[-1]]
        a, beta = geometry(r.summary)
        contact = r.summary["steps"][-1]["contact"]
        for p, row in zip(r.summary["steps"][-1]["cracks"][0]["front"], last):
            ref = closed_form_kii(mu, p["e1"], p["e2"], sigma, a)
            rows.append((mu, int(row["point"]), float(row["K_I"]), float(row["K_II"]), ref,
                         contact["slip"], contact["stick"]))
    return rows, (a, beta)


def check(rows, a: float, beta: float, sigma: float = 1.0) -> float:
    """The largest difference to the closed form relative to σ√(πa) sinβ cosβ; raises
    AssertionError beyond TOLERANCE or when the slip/stick status is not the expected one."""
    scale = sigma * math.sqrt(math.pi * a) * math.sin(beta) * math.cos(beta)
    worst = 0.0
    for mu, tip, k1, k2, ref, slip, stick in rows:
        worst = max(worst, abs(k2 - ref) / scale)
        assert abs(k2 - ref) <= TOLERANCE * scale, f"mu={mu} tip {tip}: K_II {k2:.5f}, closed form {ref:.5f}"
        assert abs(k1) <= TOLERANCE * scale, f"mu={mu} tip {tip}: K_I {k1:.3e} on a closed crack"
        if mu < math.tan(beta):
            assert stick == 0 and slip > 0, f"mu={mu}: {slip} slipping, {stick} sticking; all should slip"
        else:
            assert slip == 0 and stick > 0, f"mu={mu}: {slip} slipping, {stick} sticking; all should stick"
    return worst


def plot(rows, a: float, beta: float, path: Path, sigma: float = 1.0) -> None:
    """K_II(μ) at both tips against the closed form, written to `path` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mus = [0.005 * i for i in range(241)]
    # The closed form in the frame of the tip at b (the other tip gives the same K_II).
    e1 = (math.cos(beta), math.sin(beta))
    e2 = (-math.sin(beta), math.cos(beta))
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(mus, [closed_form_kii(m, e1, e2, sigma, a) for m in mus], "k-",
            label=r"closed form $-\sigma\sqrt{\pi a}\,(\sin\beta\cos\beta-\mu\cos^2\beta)$, 0 for $\mu\geq\tan\beta$")
    for tip, marker in [(1, "o"), (2, "x")]:
        pts = [(r[0], r[3]) for r in rows if r[1] == tip]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], marker, ls="none", label=f"fissure, tip {tip}")
    ax.axvline(math.tan(beta), color="0.6", ls=":", lw=1)
    ax.set_xlabel(r"friction coefficient $\mu$")
    ax.set_ylabel(r"$K_{II}$")
    ax.set_title(r"Closed crack at $\beta$ = %.0f°, $\sigma$ = %g, $a$ = %g" % (math.degrees(beta), sigma, a))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(out: Path = Path("out/friction_sweep"), mus=MUS) -> Path:
    rows, (a, beta) = sweep(mus, out)
    print(f"{'mu':>5} {'tip':>3} {'K_I':>10} {'K_II':>10} {'closed form':>11} {'slip':>5} {'stick':>5}")
    for mu, tip, k1, k2, ref, slip, stick in rows:
        print(f"{mu:5.2f} {tip:3d} {k1:10.2e} {k2:10.5f} {ref:11.5f} {slip:5d} {stick:5d}")
    worst = check(rows, a, beta)
    png = out / "kii_vs_friction.png"
    plot(rows, a, beta, png)
    print(f"largest difference to the closed form: {100 * worst:.2f}% of sigma*sqrt(pi*a)*sin(beta)*cos(beta); plot: {png}")
    return png


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/friction_sweep"))
