#!/usr/bin/env python3
"""Relative strengths of a tri-phosphor CFL's emission lines, and its weak
phosphor continuum, fitted to CIE F12 (data/cie_fl.csv), the 3000 K
narrow tri-band lamp that stands for a warm-white household CFL.

Line positions come from data/cfl_lines.csv (Hg I: Sansonetti, Salit and
Reader 1996; Eu3+/Tb3+ phosphor peaks: Justel, Nikol and Ronda 1998). CIE
F12 is tabulated as 5 nm band values, so each line appears only as excess
power in the bands it falls in. The model is: Gaussian lines at the fixed
positions (free, non-negative powers) plus a smooth non-negative continuum
(piecewise linear, 10 nm knots, with a second-difference penalty). The
continuum is fitted first, to the "quiet" bands (no modelled line within
6 nm), so it follows the low baseline between the lines; the lines' powers
are then fitted to what remains in every band. Both fits are non-negative
least squares on 5 nm band averages.

Writes data/cfl_model.csv. Needs numpy and scipy (pip install numpy scipy);
the program itself only reads the CSV. Run from the repository root:
    python3 scripts/fit_cfl.py
"""
import csv
import math

import numpy as np
from scipy.optimize import nnls

# (species, nm, fwhm_nm): the lines of data/cfl_lines.csv and the Eu3+
# satellites it names (587-600, 626, 650, 705-710 nm; Y2O3:Eu3+ 5D0-7F1,2,3,4 lines).
# Mercury lines of a low-pressure discharge are far narrower than 0.3 nm
# (Doppler width ~0.002 nm); 0.3 nm is under one pixel of the Amici figure
# and still three of the sampler's 0.1 nm bins. Phosphor lines are broader
# (several Stark components), 2-4 nm.
LINES = [
    ("Hg", 404.656, 0.3), ("Hg", 407.784, 0.3), ("Hg", 435.834, 0.3), ("Hg", 546.075, 0.3),
    ("Hg", 576.961, 0.3), ("Hg", 579.067, 0.3),
    ("Tb3+", 487.0, 2.5), ("Tb3+", 490.0, 2.5), ("Tb3+", 541.0, 2.0), ("Tb3+", 544.5, 2.0), ("Tb3+", 549.5, 2.0), ("Tb3+", 587.0, 4.0), ("Tb3+", 621.0, 3.0),
    ("Eu3+", 593.0, 3.0), ("Eu3+", 599.0, 3.0), ("Eu3+", 611.0, 2.0), ("Eu3+", 615.0, 2.0), ("Eu3+", 619.0, 2.0),
    ("Eu3+", 626.0, 3.0), ("Eu3+", 631.0, 3.0), ("Eu3+", 650.0, 3.0), ("Eu3+", 707.0, 3.0), ("Eu3+", 711.0, 3.0),
]
KNOTS = np.arange(380.0, 781.0, 10.0)
# Weight of the continuum's second-difference penalty. At 3 the continuum
# could not follow F12's quiet bands down into the 505-525 nm trough (1.44
# and 1.23 at 510 and 520 nm against F12's 0.92 and 0.60): that excess is
# the wash between a lamp's green and blue images through a prism. At 1 it
# reads 1.31 and 0.80 there and the whole fit is no worse (misfit 0.106
# against 0.108).
SMOOTH = 1.0
LAMP = "FL12"  # CIE F12: a 3000 K narrow tri-band lamp, the warm white of household CFLs


def fl11():
    rows = [l for l in open("data/cie_fl.csv") if not l.startswith("#")]
    r = list(csv.reader(rows))
    i = r[0].index(LAMP)
    return np.array([float(x[0]) for x in r[1:]]), np.array([float(x[i]) for x in r[1:]])


def phi(x):
    return 0.5 * (1.0 + math.erf(x / math.sqrt(2.0)))


def band_of_line(c, fwhm, centres):
    s = fwhm / math.sqrt(8.0 * math.log(2.0))
    return np.array([(phi((b + 2.5 - c) / s) - phi((b - 2.5 - c) / s)) / 5.0 for b in centres])


def band_of_hat(k, centres):
    # A hat function of half-width 10 nm at knot k, averaged over each band (fine sampling).
    out = []
    for b in centres:
        xs = np.linspace(b - 2.5, b + 2.5, 51)
        out.append(np.mean(np.clip(1.0 - np.abs(xs - k) / 10.0, 0.0, None)))
    return np.array(out)


def main():
    nm, v = fl11()
    lines = np.stack([band_of_line(c, w, nm) for _, c, w in LINES], axis=1)
    hats = np.stack([band_of_hat(k, nm) for k in KNOTS], axis=1)
    nl, nk = len(LINES), len(KNOTS)
    quiet = np.array([min(abs(b - c) for _, c, _ in LINES) > 6.0 for b in nm])
    pen = np.zeros((nk - 2, nk))
    for i in range(nk - 2):
        pen[i, i: i + 3] = SMOOTH * np.array([1.0, -2.0, 1.0])
    cont, _ = nnls(np.vstack([hats[quiet], pen]), np.concatenate([v[quiet], np.zeros(nk - 2)]))
    powers, _ = nnls(lines, np.clip(v - hats @ cont, 0.0, None))
    x = np.concatenate([powers, cont])
    fit = lines @ powers + hats @ cont
    rel = np.sqrt(np.mean((fit - v) ** 2)) / np.sqrt(np.mean(v ** 2))
    with open("data/cfl_model.csv", "w") as f:
        f.write("# A tri-phosphor compact fluorescent lamp: emission lines and the weak phosphor continuum.\n")
        f.write("# Positions: data/cfl_lines.csv (Hg I: Sansonetti, Salit & Reader, Appl. Opt. 35, 74 (1996);\n")
        f.write("# Eu3+/Tb3+: Justel, Nikol & Ronda, Angew. Chem. Int. Ed. 37, 3084 (1998)).\n")
        f.write(f"# Strengths: fitted to CIE {LAMP} (3000 K tri-band; CIE 015:2018, data/cie_fl.csv) by scripts/fit_cfl.py: Gaussian lines at\n")
        f.write("# these positions plus a smooth non-negative continuum (fitted first, to the bands with no line within 6 nm),\n# 5 nm band averages, non-negative least squares. F12 cannot separate Hg 546.1 from Tb 544 (one band).\n")
        f.write(f"# Relative RMS misfit to {LAMP}'s 5 nm bands: {rel:.3f}. kind=line: power ({LAMP} units x nm), fwhm in nm;\n")
        f.write(f"# kind=continuum: spectral power per nm at that wavelength ({LAMP} units), linear between knots.\n")
        f.write("kind,species,wavelength_nm,power,fwhm_nm\n")
        for (sp, c, w), p in zip(LINES, x[:nl]):
            f.write(f"line,{sp},{c},{p:.4f},{w}\n")
        for k, p in zip(KNOTS, x[nl:]):
            f.write(f"continuum,phosphor,{k:.0f},{p:.4f},\n")
    print(f"relative RMS misfit {rel:.4f}")
    for b, f_, w in zip(nm, fit, v):
        if abs(f_ - w) > 2.0:
            print(f"    band {b:.0f}: fit {f_:.2f} {LAMP} {w:.2f}")
    for (sp, c, w), p in zip(LINES, x[:nl]):
        print(f"  {sp:5} {c:8.3f} nm  power {p:8.2f}")
    print("  continuum:", " ".join(f"{p:.2f}" for p in x[nl:]))


if __name__ == "__main__":
    main()
