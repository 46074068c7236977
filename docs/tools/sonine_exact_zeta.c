/* sonine_exact_zeta.c - the HCS temperature ratios from the exact Boltzmann energy-loss integrals over given
 * velocity distributions (docs/physics-sonine.md Sec. 4). For each species pair (k, i) P random pairs of the
 * samples give the rate of change of <v_k^2>,
 *   d<v_k^2>/dt = sum_i n_i sigma_ki^2 E[(pi/2) A g (A g^2 - 2 g.v1)],  A = (1 + eps) m_i/(m_k + m_i),
 * (the hemisphere integral of Sec. 2 done in closed form), zeta_k = -(d<v_k^2>/dt)/<v_k^2>; the shapes are kept
 * and each species' velocities scaled until all zeta_k are equal (Newton on log T_k/T_1; the same pairs at
 * every step). The samples: the DSMC velocities written by sonine_dsmc_moments.c, or Maxwellians at the same
 * temperatures, optionally weighted by 1 + a2 S2(c^2) + a3 S3(c^2) (exact products of the weights, no
 * linearisation), species by species as MODE says.
 *   cc -O2 docs/tools/sonine_exact_zeta.c -lm -o /tmp/sez
 *   /tmp/sez vel.bin binary|ternary N MODE P seed [a2_1 a3_1 a2_2 a3_2 ...]
 * MODE: one letter per species: d = the DSMC sample, g = a Maxwellian at its temperature, s = a Maxwellian
 * weighted by the Sonine polynomials with the given a2_k, a3_k. Prints zeta_k at the DSMC state and the
 * solved ratios T_k/T_1; the se of the ratios from 8 independent blocks of P/8 pairs. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rs;
static inline uint64_t next(void) {
  uint64_t z = (rs += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static inline double unif(void) { return (next() >> 11) * 0x1.0p-53; }
static double gauss(void) {
  static int have = 0;
  static double keep;
  if (have) return have = 0, keep;
  double u = unif(), w = unif();
  if (u < 1e-300) u = 1e-300;
  double r = sqrt(-2 * log(u));
  keep = r * sin(2 * M_PI * w), have = 1;
  return r * cos(2 * M_PI * w);
}

enum { MMAX = 3 };
static int M;
static int64_t N;
static double m[MMAX], sg[MMAX], n[MMAX], eps = 0.5;
static double *V[MMAX], *W[MMAX]; /* velocities and weights (W = NULL: 1) */
static double v2[MMAX];           /* weighted <v^2> of each sample */

/* pair sums: S[k][i] = E[w1 w2 (pi/2) A g (A g^2 - 2 g.v1)] over fixed random pairs, as a function of the
 * scale factors q_k (v -> q_k v); pairs listed once in idx */
static int64_t P;
static int32_t *I1[MMAX][MMAX], *I2[MMAX][MMAX];

static void zetas(const double *q, int64_t lo, int64_t hi, double *zeta) {
  for (int k = 0; k < M; k++) {
    double rate = 0;
    for (int i = 0; i < M; i++) {
      const double A = (1 + eps) * m[i] / (m[k] + m[i]), sk = 0.5 * (sg[k] + sg[i]);
      double s = 0, sw = 0;
      for (int64_t p = lo; p < hi; p++) {
        const double *a = V[k] + 3 * I1[k][i][p], *b = V[i] + 3 * I2[k][i][p];
        const double w = (W[k] ? W[k][I1[k][i][p]] : 1) * (W[i] ? W[i][I2[k][i][p]] : 1);
        double g[3], gg = 0, gv = 0;
        for (int d = 0; d < 3; d++) g[d] = q[k] * a[d] - q[i] * b[d], gg += g[d] * g[d], gv += g[d] * q[k] * a[d];
        s += w * 0.5 * M_PI * A * sqrt(gg) * (A * gg - 2 * gv);
        sw += w;
      }
      rate += n[i] * sk * sk * s / sw;
    }
    zeta[k] = -rate / (q[k] * q[k] * v2[k]);
  }
}

/* the fourth-moment balance at the sample (q = 1): d<v^4>/dt from the hemisphere integrals
 *   I(a, b) = Int Theta(x) x^a (v1.n)^b dn, x = ghat.n:  I(a, 0) = 2 pi/(a + 1), I(a, 1) = 2 pi u/(a + 2),
 *   I(a, 2) = 2 pi [u^2/(a + 3) + (v1^2 - u^2)(1/(a + 1) - 1/(a + 3))/2],  u = v1.ghat,
 * d<v^4>/dt per pair = Int (g.n) [2 v1^2 D + D^2] dn, D = -2 A (g.n)(v1.n) + A^2 (g.n)^2. Prints, per species,
 * (1 + a2)(R4/<v^4> - 2 R2/<v^2>)/zeta = (da2/dt)/zeta (0 in a stationary scaled state) */
static void balance4(void) {
  for (int k = 0; k < M; k++) {
    double r2 = 0, r4 = 0;
    for (int i = 0; i < M; i++) {
      const double A = (1 + eps) * m[i] / (m[k] + m[i]), sk = 0.5 * (sg[k] + sg[i]);
      double s2 = 0, s4 = 0, s6r = 0, sw = 0;
      for (int64_t p = 0; p < P; p++) {
        const double *a = V[k] + 3 * I1[k][i][p], *b = V[i] + 3 * I2[k][i][p];
        const double w = (W[k] ? W[k][I1[k][i][p]] : 1) * (W[i] ? W[i][I2[k][i][p]] : 1);
        double g[3], gg = 0, gv = 0, vv = 0;
        for (int d = 0; d < 3; d++) g[d] = a[d] - b[d], gg += g[d] * g[d], gv += g[d] * a[d], vv += a[d] * a[d];
        const double gn = sqrt(gg), u = gv / gn, t = 2 * M_PI;
#define I0(a_) (t / ((a_) + 1.0))
#define I1f(a_) (t * u / ((a_) + 2.0))
#define I2f(a_) (t * (u * u / ((a_) + 3.0) + 0.5 * (vv - u * u) * (1.0 / ((a_) + 1.0) - 1.0 / ((a_) + 3.0))))
        const double R2p = -2 * A * gg * I1f(2) + A * A * gg * gn * I0(3);
        const double R4p = 2 * vv * R2p + 4 * A * A * gg * gn * I2f(3) - 4 * A * A * A * gg * gg * I1f(4) +
                           A * A * A * A * gg * gg * gn * I0(5);
        /* d<v^6>/dt: v1'^6 - v1^6 = 3 X^2 D + 3 X D^2 + D^3 (X = v1^2), D = al + be, al = -2 A g x (v1.n),
         * be = A^2 g^2 x^2; the term al^p be^q times (g.n) gives (-2A)^p A^(2q) g^(1+p+2q) I(1+p+2q, p) */
        double R6p = 0;
        {
          const int P_[10] = {1, 0, 2, 1, 0, 3, 2, 1, 0, 0}, Q_[10] = {0, 1, 0, 1, 2, 0, 1, 2, 3, 0};
          const double C_[9] = {3 * vv * vv, 3 * vv * vv, 3 * vv, 6 * vv, 3 * vv, 1, 3, 3, 1};
          for (int tt = 0; tt < 9; tt++) {
            const int pp = P_[tt], qq = Q_[tt], aa = 1 + pp + 2 * qq;
            double I;
            if (pp == 0) I = I0(aa);
            else if (pp == 1) I = I1f(aa);
            else if (pp == 2) I = I2f(aa);
            else I = t * (u * u * u / (aa + 4.0) + 1.5 * u * (vv - u * u) * (1.0 / (aa + 2.0) - 1.0 / (aa + 4.0)));
            R6p += C_[tt] * pow(-2 * A, pp) * pow(A, 2 * qq) * pow(gn, aa) * I;
          }
        }
        s2 += w * R2p, s4 += w * R4p, s6r += w * R6p, sw += w;
      }
      r2 += n[i] * sk * sk * s2 / sw, r4 += n[i] * sk * sk * s4 / sw;
      printf("  pair (%d, %d): d<v^2>/dt %.10g, d<v^4>/dt %.10g, d<v^6>/dt %.10g\n", k + 1, i + 1,
             n[i] * sk * sk * s2 / sw, n[i] * sk * sk * s4 / sw, n[i] * sk * sk * s6r / sw);
    }
    /* <v^4> of the sample (weighted) */
    double sw = 0, s4 = 0;
    for (int64_t j = 0; j < N; j++) {
      const double w = W[k] ? W[k][j] : 1;
      double x = 0;
      for (int d = 0; d < 3; d++) x += V[k][3 * j + d] * V[k][3 * j + d];
      sw += w, s4 += w * x * x;
    }
    const double v4 = s4 / sw, a2 = 0.6 * v4 / (v2[k] * v2[k]) - 1, zeta = -r2 / v2[k];
    double s6 = 0;
    for (int64_t j = 0; j < N; j++) {
      const double wj = W[k] ? W[k][j] : 1;
      double x = 0;
      for (int d = 0; d < 3; d++) x += V[k][3 * j + d] * V[k][3 * j + d];
      s6 += wj * x * x * x;
    }
    const double a3 = 1 + 3 * a2 - (9.0 / 35.0) * (s6 / sw) / (v2[k] * v2[k] * v2[k]);
    printf("  species %d: sample <v^2> %.10g, a2 %+.5f, a3 %+.5f, (da2/dt)/zeta = %+.4f\n", k + 1, v2[k], a2, a3,
           (1 + a2) * (r4 / v4 - 2 * r2 / v2[k]) / zeta);
  }
}

/* solve zeta_k(q) = zeta_1 for log q_k, k >= 2 (q_1 = 1), Newton with finite differences */
static void solve(int64_t lo, int64_t hi, double *ratio) {
  double q[MMAX] = {1, 1, 1}, z[MMAX], zp[MMAX];
  for (int it = 0; it < 30; it++) {
    zetas(q, lo, hi, z);
    double F[MMAX], J[MMAX][MMAX], fm = 0;
    for (int k = 1; k < M; k++) F[k] = log(z[k] / z[0]), fm = fmax(fm, fabs(F[k]));
    if (fm < 1e-12) break;
    for (int j = 1; j < M; j++) {
      double qq[MMAX] = {q[0], q[1], q[2]};
      qq[j] *= exp(1e-5);
      zetas(qq, lo, hi, zp);
      for (int k = 1; k < M; k++) J[k][j] = (log(zp[k] / zp[0]) - F[k]) / 1e-5;
    }
    double d[MMAX] = {0};
    if (M == 2) d[1] = -F[1] / J[1][1];
    else {
      const double det = J[1][1] * J[2][2] - J[1][2] * J[2][1];
      d[1] = -(F[1] * J[2][2] - F[2] * J[1][2]) / det;
      d[2] = -(J[1][1] * F[2] - J[2][1] * F[1]) / det;
    }
    for (int k = 1; k < M; k++) q[k] *= exp(d[k]);
  }
  for (int k = 0; k < M; k++) ratio[k] = q[k] * q[k] * m[k] * v2[k] / (m[0] * v2[0]);
}

int main(int argc, char **argv) {
  if (argc < 7) return fprintf(stderr, "usage: %s vel.bin binary|ternary N MODE P seed [a2 a3 ...]\n", argv[0]), 2;
  M = !strcmp(argv[2], "ternary") ? 3 : 2;
  N = atoll(argv[3]);
  const char *mode = argv[4];
  P = atoll(argv[5]);
  rs = strtoull(argv[6], NULL, 10);
  const double mm[3] = {1, 100, 500};
  double a2[MMAX] = {0}, a3[MMAX] = {0};
  for (int k = 0; k < M; k++) {
    m[k] = mm[k], sg[k] = cbrt(mm[k]), n[k] = 0.1;
    if (argc > 7 + 2 * k) a2[k] = atof(argv[7 + 2 * k]);
    if (argc > 8 + 2 * k) a3[k] = atof(argv[8 + 2 * k]);
  }
  FILE *f = fopen(argv[1], "rb");
  if (!f) return fprintf(stderr, "cannot open %s\n", argv[1]), 1;
  for (int k = 0; k < M; k++) {
    V[k] = malloc(sizeof(double) * 3 * N);
    if (fread(V[k], sizeof(double), 3 * N, f) != (size_t)(3 * N)) return fprintf(stderr, "short file\n"), 1;
    double u[3] = {0}, s2 = 0;
    for (int64_t j = 0; j < N; j++)
      for (int d = 0; d < 3; d++) u[d] += V[k][3 * j + d] / N;
    for (int64_t j = 0; j < N; j++)
      for (int d = 0; d < 3; d++) V[k][3 * j + d] -= u[d], s2 += V[k][3 * j + d] * V[k][3 * j + d] / N;
    W[k] = NULL;
    if (mode[k] == 'g' || mode[k] == 's') { /* Maxwellian of the same <v^2> (weights for 's') */
      const double sd = sqrt(s2 / 3);
      for (int64_t j = 0; j < 3 * N; j++) V[k][j] = sd * gauss();
      if (mode[k] == 's') {
        W[k] = malloc(sizeof(double) * N);
        for (int64_t j = 0; j < N; j++) {
          double x = 0;
          for (int d = 0; d < 3; d++) x += V[k][3 * j + d] * V[k][3 * j + d];
          x /= 2 * sd * sd; /* c^2 */
          const double S2 = x * x / 2 - 2.5 * x + 15.0 / 8, S3 = -x * x * x / 6 + 1.75 * x * x - 35.0 / 8 * x + 35.0 / 16;
          W[k][j] = 1 + a2[k] * S2 + a3[k] * S3;
        }
      }
    }
    double sw = 0, s = 0;
    for (int64_t j = 0; j < N; j++) {
      const double w = W[k] ? W[k][j] : 1;
      sw += w;
      for (int d = 0; d < 3; d++) s += w * V[k][3 * j + d] * V[k][3 * j + d];
    }
    v2[k] = s / sw;
  }
  fclose(f);
  for (int k = 0; k < M; k++)
    for (int i = 0; i < M; i++) {
      I1[k][i] = malloc(sizeof(int32_t) * P), I2[k][i] = malloc(sizeof(int32_t) * P);
      for (int64_t p = 0; p < P; p++) {
        I1[k][i][p] = (int32_t)(unif() * N);
        do I2[k][i][p] = (int32_t)(unif() * N);
        while (i == k && I2[k][i][p] == I1[k][i][p]);
      }
    }
  double q1[MMAX] = {1, 1, 1}, z[MMAX], r[MMAX], rb[8][MMAX];
  zetas(q1, 0, P, z);
  solve(0, P, r);
  for (int b = 0; b < 8; b++) solve(b * (P / 8), (b + 1) * (P / 8), rb[b]);
  printf("%s P=%lld: zeta_k at the sample's temperatures", mode, (long long)P);
  for (int k = 0; k < M; k++) printf(" %.6g", z[k]);
  printf("; sample T_k/T_1");
  for (int k = 1; k < M; k++) printf(" %.4f", m[k] * v2[k] / (m[0] * v2[0]));
  printf("; equal-zeta T_k/T_1");
  for (int k = 1; k < M; k++) {
    double s = 0, s2 = 0;
    for (int b = 0; b < 8; b++) s += rb[b][k] / 8;
    for (int b = 0; b < 8; b++) s2 += (rb[b][k] - s) * (rb[b][k] - s) / 7;
    printf(" %.4f (se %.4f)", r[k], sqrt(s2 / 8));
  }
  printf("\n");
  balance4();
  return 0;
}
