#!/usr/bin/env python3
"""The moment balances of one DSMC snapshot, exact against the linear second Sonine level at the same state
(docs/physics-sonine.md Sec. 4). Input: the output of docs/tools/sonine_exact_zeta.c in mode dd (one or more
runs with different pair seeds over the same snapshot of the binary m = 1, 100 set-up): per pair (k, i) the
exact d<v^2>/dt, d<v^4>/dt, d<v^6>/dt over the DSMC velocities, and per species <v^2>, a2, a3 of the snapshot.
Prints, per pair, theory/exact - 1 of the three rates (the second Sonine pair terms of sonine_second.py at the
snapshot's T_k, a2_k, a3_k; "a2 only": a3 = 0), and per species (da2/dt)/zeta and (da3/dt)/zeta, exact
(from the exact rates and the snapshot's moments, no linearisation) and second Sonine; se over the pair seeds.

  for s in 21 22 23 24; do /tmp/sez /tmp/vel_bin.bin binary 100000 dd 8000000 $s; done > /tmp/pairs.txt
  python3 docs/tools/sonine_second.py > /dev/null; python3 docs/tools/sonine_balance_check.py /tmp/pairs.txt
"""
import math
import os
import re
import statistics as st
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sonine_second as S  # noqa: E402

f = S.load()
txt = open(sys.argv[1]).read()
pr = {}
for k, i, r2, r4, r6 in re.findall(
        r"pair \((\d), (\d)\): d<v\^2>/dt (\S+), d<v\^4>/dt ([^,]+), d<v\^6>/dt (\S+)", txt):
    pr.setdefault((int(k) - 1, int(i) - 1), []).append((float(r2), float(r4), float(r6)))
sp_ = {}
for k, v2, a2, a3 in re.findall(r"species (\d): sample <v\^2> (\S+), a2 ([^,]+), a3 ([^,]+),", txt):
    sp_[int(k) - 1] = (float(v2), float(a2), float(a3))
m, sig, n, eps = [1.0, 100.0], [1.0, 100 ** (1 / 3)], [0.1, 0.1], 0.5
M = 2
for (k, i), vals in sorted(pr.items()):
    akv, aiv = sp_[k][0] / 3, sp_[i][0] / 3
    A = (1 + eps) * m[i] / (m[k] + m[i])
    w = math.sqrt(2 * math.pi) * n[i] * (0.5 * (sig[k] + sig[i])) ** 2

    def th(p, with_a3):
        s2 = akv + aiv  # in units of s^2 (the snapshot's temperatures are tiny)
        c = {key: fn(akv / s2, aiv / s2, A) * s2 ** ((p + 1) / 2) for key, fn in f.items() if key[0] == p}
        x = c[(p, "0")] + c[(p, "a2k")] * sp_[k][1] + c[(p, "a2i")] * sp_[i][1]
        if with_a3:
            x += c[(p, "a3k")] * sp_[k][2] + c[(p, "a3i")] * sp_[i][2]
        return w * x
    for j, p in enumerate((2, 4, 6)):
        r = [v[j] for v in vals]
        mean, se = st.mean(r), st.stdev(r) / math.sqrt(len(r))
        print("pair (%d, %d) d<v^%d>/dt: se %.1e (relative); theory/exact - 1: a2 only %+.2e, a2 and a3 %+.2e"
              % (k + 1, i + 1, p, se / abs(mean), th(p, False) / mean - 1, th(p, True) / mean - 1))
nseed = len(pr[(0, 0)])
for k in range(M):
    v2, a2s, a3s = sp_[k]
    ak_ = v2 / 3
    v4, v6 = 15 * ak_ ** 2 * (1 + a2s), 105 * ak_ ** 3 * (1 + 3 * a2s - a3s)
    e2, e3 = [], []
    for j in range(nseed):
        R2, R4, R6 = (sum(pr[(k, i)][j][q] for i in range(M)) for q in range(3))
        dadt, zeta = R2 / 3, -R2 / v2
        da2 = R4 / (15 * ak_ ** 2) - 2 * v4 / (15 * ak_ ** 3) * dadt
        da3 = 3 * da2 - R6 / (105 * ak_ ** 3) + 3 * v6 / (105 * ak_ ** 4) * dadt
        e2.append(da2 / zeta)
        e3.append(da3 / zeta)
    T = [sp_[i][0] / 3 * m[i] / (sp_[0][0] / 3 * m[0]) for i in range(M)]
    z, p2, p3 = S.rates(f, m, sig, n, eps, T, [sp_[i][1] for i in range(M)], [sp_[i][2] for i in range(M)], 2)
    print("species %d: (da2/dt)/zeta exact %+.4f (se %.4f), second Sonine %+.4f; (da3/dt)/zeta exact %+.4f "
          "(se %.4f), second Sonine %+.4f" % (k + 1, st.mean(e2), st.stdev(e2) / math.sqrt(nseed), p2[k] / z[k],
                                                st.mean(e3), st.stdev(e3) / math.sqrt(nseed), p3[k] / z[k]))
