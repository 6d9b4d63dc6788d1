"""Run CONTACT (Vollebregt & Kalker's exact rolling-contact program) on Hertzian
steady-rolling cases given in EXPRESS's normalised creepages, and read its forces.

This script is not part of the package: it makes the test data and the package table of
:mod:`express.rail.creep_table`.  CONTACT is built from its public source
(github.com/eve70a/CONTACT, commit d431cdb, Apache-2.0) with gfortran, as described in
``tests/data/contact_exact/README.md``; give its executable with ``--contact`` or the
``CONTACT_EXE`` environment variable.  Without it the script says so and stops.

Each case is a row ``(a/b, u_x, u_y, u_phi)`` of normalised creepages
(``docs/contact.md``, "Creep forces from tables of the exact theory"): with
``c = sqrt(ab)`` and Kalker's ``C11, C22, C23`` at ``a/b`` and ``nu``::

    u_x = G ab C11 xi / (3 mu N),  u_y = G ab C22 eta / (3 mu N),
    u_phi = G (ab)^1.5 C23 phi / (3 mu N)

The contact is run at ``c = 6 mm``, ``N = 80 kN``, ``mu = 0.3``, ``G = 82 GPa`` on a
``grid x grid`` mesh of the ellipse (potential area 1.05 times the ellipse); the result per
case is ``(Fx, Fy) / (mu N)`` and ``Mz / (mu N c)`` as CONTACT prints them (on body 1).

    python tools/contact_creep_runs.py table  OUT.npz  [--contact EXE] [--jobs 2]
    python tools/contact_creep_runs.py cases OUT.csv --cases IN.csv [--contact EXE]

(``IN.csv``: a header, then rows ``regime`` and :data:`COLUMNS`; ``OUT.csv`` adds CONTACT's
``FX, FY [N], MZ [N mm]``.)
"""

from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from express.rail.kalker import kalker_coefficients

POISSON = 0.3
SHEAR = 82000.0  # N/mm^2
NORMAL = 80000.0  # N
FRICTION = 0.3
SIZE = 6.0  # sqrt(ab) [mm]
SCALE = 1.05

_BLOCK = """  203100     P-B-T-N-F-S        PVTIME, BOUND , TANG  , NORM , FORCE, STRESS
  022020     L-D-C-M-Z-E        FRCLAW, DISCNS, INFLCF, MATER, RZNORM, EXRHS
 000020{ret}   H-G-I-A-O-W-R  HEAT, GAUSEI, IESTIM, MATFIL, OUTPUT, FLOW, RETURN
   100  400    8    1      1e-6    MAXGS , MAXIN , MAXNR , MAXOUT, EPS
 {fn:.6e}  {cksi:.9e}  {ceta:.9e}  {cphi:.9e}  FN, CKSI, CETA, CPHI
   {mu:.3f}      {mu:.3f}                                 FSTAT, FKIN
   0.000      1.000      30000.                     CHI, DQ, VELOC
   {nu:.3f}      {nu:.3f}      {gg:.1f}     {gg:.1f}          POISS 1,2,  GG 1,2
   -3                                               IPOTCN
   {mx}   {my}     {aa:.9f}      {bb:.9f}      {scale:.3f}          MX,MY,AA,BB,SCALE
"""


def physical(cases: np.ndarray) -> np.ndarray:
    """CONTACT's inputs of normalised cases (rows ``a/b, u_x, u_y, u_phi``) at the fixed
    contact (``c``, ``N``, ``mu``, ``G`` above): rows of :data:`COLUMNS`."""
    rows = []
    for ratio, ux, uy, uphi in cases:
        aa, bb = SIZE * math.sqrt(ratio), SIZE / math.sqrt(ratio)
        c11, c22, c23, _ = kalker_coefficients(aa, bb, POISSON)
        limit = 3.0 * FRICTION * NORMAL
        area = SHEAR * aa * bb
        rows.append((aa, bb, NORMAL, FRICTION, SHEAR, limit * ux / (area * c11), limit * uy / (area * c22),
                     limit * uphi / (area * SIZE * c23)))
    return np.array(rows)


#: A physical case: semi-axes [mm], normal force [N], mu, G [N/mm^2], creepages (CPHI in rad/mm).
COLUMNS = ("aa_mm", "bb_mm", "fn_N", "mu", "gg_N_per_mm2", "cksi", "ceta", "cphi_per_mm")


def input_text(cases: np.ndarray, grid: int) -> str:
    """CONTACT's input file of physical ``cases`` (rows of :data:`COLUMNS`)."""
    blocks = []
    for k, (aa, bb, fn, mu, gg, cksi, ceta, cphi) in enumerate(cases):
        blocks.append(_BLOCK.format(ret=1 if k == len(cases) - 1 else 0, fn=fn, cksi=cksi, ceta=ceta,
                                    cphi=cphi, mu=mu, nu=POISSON, gg=gg, mx=round(grid * SCALE),
                                    my=round(grid * SCALE), aa=aa, bb=bb, scale=SCALE))
    return " 3 MODULE\n" + "\n".join(blocks) + "\n 0 MODULE\n"


_FORCES = re.compile(r"FN/G\s+FX/FSTAT/FN\s+FY/FSTAT/FN.*\n\s*(\S+)\s+(\S+)\s+(\S+)")
_TOTALS = re.compile(r"FN\s+FX\s+FY\s+MZ\s+ELAST.*\n\s*(\S+)\s+(\S+)\s+(\S+)\s+(\S+)")


def run(executable: str, cases: np.ndarray, grid: int) -> np.ndarray:
    """CONTACT's ``(FX [N], FY [N], MZ [N mm])`` on body 1 of physical ``cases`` (rows of
    :data:`COLUMNS`), shape ``(n, 3)``."""
    with tempfile.TemporaryDirectory() as folder:
        Path(folder, "cases.inp").write_text(input_text(cases, grid))
        subprocess.run([executable, "2", "cases"], cwd=folder, check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL, timeout=36000)
        text = Path(folder, "cases.out").read_text()
    totals = _TOTALS.findall(text)
    if len(totals) != len(cases):
        raise RuntimeError(f"CONTACT gave {len(totals)} results for {len(cases)} cases")
    return np.array([[float(t[1]), float(t[2]), float(t[3])] for t in totals])


def normalised(executable: str, cases: np.ndarray, grid: int) -> np.ndarray:
    """``(Fx / (mu N), Fy / (mu N), Mz / (mu N c))`` of normalised cases (rows ``a/b, u_x, u_y,
    u_phi``), shape ``(n, 3)``."""
    limit = FRICTION * NORMAL
    return run(executable, physical(cases), grid) / np.array([limit, limit, limit * SIZE])


def run_parallel(executable: str, cases: np.ndarray, grid: int, jobs: int, chunk: int = 100,
                 cache: Path | None = None, runner: Callable = normalised) -> np.ndarray:
    """``runner`` (:func:`normalised` or :func:`run`) in chunks of ``chunk`` cases on ``jobs`` threads (each a CONTACT process);
    with ``cache`` each chunk's result is kept in that folder, and reused when rerun."""
    parts = [cases[i:i + chunk] for i in range(0, len(cases), chunk)]

    def one(k: int) -> np.ndarray:
        path = None if cache is None else cache / f"chunk{k:04d}_{grid}.npy"
        if path is not None and path.exists():
            kept = np.load(path)
            if kept.shape[0] == len(parts[k]):
                return kept
        result = runner(executable, parts[k], grid)
        if path is not None:
            np.save(path, result)
        return result

    if cache is not None:
        cache.mkdir(parents=True, exist_ok=True)
    with ThreadPoolExecutor(jobs) as pool:
        return np.concatenate(list(pool.map(one, range(len(parts)))))


def _executable(given: str | None) -> str:
    exe = given or os.environ.get("CONTACT_EXE") or shutil.which("contact_linux64")
    if not exe or not Path(exe).exists():
        sys.exit("CONTACT's executable not found: build it (tests/data/contact_exact/README.md) and give "
                 "--contact EXE or CONTACT_EXE")
    return exe


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("what", choices=("table", "cases"))
    parser.add_argument("out", help="table: the .npz; cases: the CSV written")
    parser.add_argument("--contact", help="CONTACT's executable (default: $CONTACT_EXE)")
    parser.add_argument("--jobs", type=int, default=1, help="CONTACT processes at once")
    parser.add_argument("--grid", type=int, default=None, help="elements along each axis of the ellipse "
                        "(default 40 for the table, 60 for cases)")
    parser.add_argument("--cases", help="for 'cases': a CSV with columns a/b, u_x, u_y, u_phi")
    parser.add_argument("--cache", help="a folder to keep each chunk's results in (a rerun resumes)")
    args = parser.parse_args()
    exe = _executable(args.contact)
    cache = Path(args.cache) if args.cache else None
    if args.what == "cases":
        cases = np.loadtxt(args.cases, delimiter=",", skiprows=1, usecols=range(1, 9), ndmin=2)
        labels = np.loadtxt(args.cases, delimiter=",", skiprows=1, usecols=0, dtype=str, ndmin=1)
        forces = run_parallel(exe, cases, args.grid or 60, args.jobs, cache=cache, runner=run)
        with open(args.out, "w") as out:
            out.write(",".join(("regime", *COLUMNS, "fx_N", "fy_N", "mz_Nmm")) + "\n")
            for label, row, force in zip(labels, cases, forces, strict=True):
                out.write(",".join([label, *(f"{v:.9g}" for v in (*row, *force))]) + "\n")
        return
    from creep_table_build import build_table

    build_table(Path(args.out), lambda cases: run_parallel(exe, cases, args.grid or 40, args.jobs, cache=cache),
                args.grid or 40)


if __name__ == "__main__":
    main()
