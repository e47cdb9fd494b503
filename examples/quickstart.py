"""hopperflow from Python in five steps: run a case, plot W(t) and v(x), sweep three outlet
widths, and fit the two-dimensional Beverloo law W = C ρ √g (D − k d)^{3/2}.

    python examples/quickstart.py            # the paper's base case and fan2023-sized runs
    python examples/quickstart.py --small    # a 250-sphere hopper: seconds instead of minutes

Figures and runs go to --out (default out/quickstart). Needs numpy and matplotlib; pandas
is optional.
"""

import argparse
import math
from pathlib import Path

import numpy as np

import hopperflow as hf

HERE = Path(__file__).resolve().parent
SMALL_CASE = HERE.parent / "crates" / "python" / "tests" / "cases" / "tiny.toml"


def column(table, name):
    """A column as a numpy array, from a DataFrame or from a dict of arrays."""
    return np.asarray(table[name], dtype=float)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--small", action="store_true", help="a 250-sphere hopper (seconds)")
    parser.add_argument("--out", default="out/quickstart", help="folder of runs and figures")
    parser.add_argument("--jobs", type=int, default=None, help="cases run at once in the sweep")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    # 1. One run: the base case (or the small one), as `hopperflow run` would do it.
    case = hf.Case.load(str(SMALL_CASE)) if args.small else hf.Case.paper()
    run = hf.run(case, out=out / "base", restart=True, pictures=False)
    s = run.summary
    print(f"W = {s['discharge_rate'] * 1e3:.2f} ± {s['discharge_rate_error'] * 1e3:.2f} g/s")

    # 2. W(t) and the outlet velocity profile v(x).
    flow, profiles = run.flow, run.profiles
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(column(flow, "time"), column(flow, "rate") * 1e3)
    ax1.set(xlabel="time after opening t [s]", ylabel="discharge rate W [g/s]", title="W(t)")
    ax2.plot(column(profiles, "x") * 1e3, column(profiles, "velocity"), "o-")
    ax2.set(xlabel="x [mm]", ylabel="vertical velocity v [m/s]", title="v(x) at the outlet")
    fig.tight_layout()
    fig.savefig(out / "base.png", dpi=100)
    print(f"wrote {out / 'base.png'}")

    # 3. Three outlet widths: a sweep file of the small hopper, or the paper's widths.
    sweep = out / "outlets.toml"
    if args.small:
        widths = [0.018, 0.024, 0.030]
        base = f'base = "{SMALL_CASE.as_posix()}"\n'
    else:
        # The paper's hopper, stopped once the steady window (15-70 % discharged) is complete.
        widths = [0.018, 0.030, 0.045]
        base = "[base]\nversion = 1\n[base.protocol]\nstop_fraction = 0.7\n"
    sweep.write_text(
        'version = 1\nname = "outlets"\nreplicas = 1\n'
        + base
        + '[[axes]]\nkey = "geometry.outlet_width"\n'
        + f'values = {widths}\nlabel = "D"\nscale = 1000.0\ndigits = 3\n'
    )
    study = hf.study(str(sweep), out=out / "outlets", jobs=args.jobs)
    results = study.results
    D = column(results, "outlet_width")
    W = column(results, "discharge_rate")
    order = np.argsort(D)
    D, W = D[order], W[order]

    # 4. Beverloo in two dimensions: W^{2/3} is linear in D, W^{2/3} = a (D − k d) with
    #    a = (C ρ Z √g)^{2/3}; the packing fraction is part of C.
    d = case["particles.diameter"]
    a, b = np.polyfit(D, W ** (2.0 / 3.0), 1)
    k = -b / (a * d)
    rho = case["particles.material.density"] * case["geometry.thickness"]
    C = a**1.5 / (rho * math.sqrt(9.81))
    print(f"Beverloo fit: k = {k:.2f}, C = {C:.3f}")

    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(D * 1e3, W * 1e3, "o", label="hopperflow")
    grid = np.linspace(D.min(), D.max(), 50)
    ax.plot(grid * 1e3, np.clip(a * (grid - k * d), 0, None) ** 1.5 * 1e3, "-", label=f"Beverloo, k = {k:.2f}")
    ax.set(xlabel="outlet width D [mm]", ylabel="W [g/s]", title="W(D)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "beverloo.png", dpi=100)
    print(f"wrote {out / 'beverloo.png'}")


if __name__ == "__main__":
    main()
