/* t301-particles.c - structure-of-arrays particles: add / swap_remove against a reference model,
 * growth keeps contents, swap_remove moves every array, optional arrays NULL without their flag
 * and memory() counting only what is allocated, errors. */
#include "granary_test.h"

/* Reference model: plain arrays of records, removal by moving the last record. */
typedef struct {
  double v[3], r[3], t_last, x[3], mass;
  int32_t species;
} record;

static void assert_matches(const gran_particles *p, const record *ref, int64_t n) {
  assert_int_equal(p->n, n);
  assert_true(p->capacity >= n);
  for (int64_t i = 0; i < n; i++) {
    for (int d = 0; d < 3; d++) assert_true(p->v[3 * i + d] == ref[i].v[d]);
    assert_int_equal(p->species[i], ref[i].species);
    if (p->r) {
      for (int d = 0; d < 3; d++) assert_true(p->r[3 * i + d] == ref[i].r[d]);
      assert_true(p->t_last[i] == ref[i].t_last);
    }
    if (p->x)
      for (int d = 0; d < 3; d++) assert_true(p->x[3 * i + d] == ref[i].x[d]);
    if (p->mass) assert_true(p->mass[i] == ref[i].mass);
  }
}

/* Random adds and removals with every flag combination; optional arrays are written with
 * distinct values after each add so that swap_remove must move them too. */
static void test_against_reference(void **state) {
  (void)state;
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 301));
  for (int flags = 0; flags < 8; flags++) {
    gran_particles p;
    GRAN_ASSERT_OK(gran_particles_init(&p, 3, flags));
    record *ref = malloc(sizeof(record) * 5000);
    assert_non_null(ref);
    int64_t n = 0, maxcap = p.capacity;
    for (int step = 0; step < 20000; step++) {
      double u[2];
      GRAN_ASSERT_OK(gran_rng_uniform(&g, 2, u));
      if (n == 0 || (u[0] < 0.6 && n < 5000)) {
        record r;
        memset(&r, 0, sizeof r);
        GRAN_ASSERT_OK(gran_rng_normal(&g, 3, r.v));
        r.species = (int32_t)(u[1] * 17);
        int64_t idx = -1;
        GRAN_ASSERT_OK(gran_particles_add(&p, r.v, r.species, &idx));
        assert_int_equal(idx, n);
        /* the new particle's optional arrays are zero */
        if (p.r) assert_true(p.r[3 * idx] == 0 && p.r[3 * idx + 1] == 0 && p.r[3 * idx + 2] == 0 && p.t_last[idx] == 0);
        if (p.x) assert_true(p.x[3 * idx] == 0 && p.x[3 * idx + 1] == 0 && p.x[3 * idx + 2] == 0);
        if (p.mass) assert_true(p.mass[idx] == 0);
        for (int d = 0; d < 3; d++) {
          r.r[d] = step + 0.1 * d;
          r.x[d] = -step - 0.2 * d;
        }
        r.t_last = 0.5 * step;
        r.mass = 1.0 + step;
        if (p.r) {
          memcpy(p.r + 3 * idx, r.r, sizeof r.r);
          p.t_last[idx] = r.t_last;
        }
        if (p.x) memcpy(p.x + 3 * idx, r.x, sizeof r.x);
        if (p.mass) p.mass[idx] = r.mass;
        ref[n++] = r;
      } else {
        const int64_t i = (int64_t)(u[1] * (double)n);
        GRAN_ASSERT_OK(gran_particles_swap_remove(&p, i));
        ref[i] = ref[--n];
      }
      if (p.capacity > maxcap) maxcap = p.capacity;
      if (step % 97 == 0) assert_matches(&p, ref, n);
    }
    assert_matches(&p, ref, n);
    /* geometric growth: capacity never more than twice the largest population (and >= 16) */
    assert_true(maxcap <= 2 * 5000);
    /* arrays present exactly when their flag is set */
    assert_true((p.r != NULL) == ((flags & GRAN_PARTICLES_DISPLACEMENT) != 0));
    assert_true((p.t_last != NULL) == ((flags & GRAN_PARTICLES_DISPLACEMENT) != 0));
    assert_true((p.x != NULL) == ((flags & GRAN_PARTICLES_POSITION) != 0));
    assert_true((p.mass != NULL) == ((flags & GRAN_PARTICLES_MASS) != 0));
    assert_int_equal(p.flags, flags);
    GRAN_ASSERT_OK(gran_particles_free(&p));
    free(ref);
  }
}

static void test_growth_keeps_contents(void **state) {
  (void)state;
  gran_particles p;
  GRAN_ASSERT_OK(gran_particles_init(&p, 0, GRAN_PARTICLES_DISPLACEMENT | GRAN_PARTICLES_MASS));
  assert_null(p.v);
  assert_int_equal(p.capacity, 0);
  int64_t ngrow = 0, cap = 0;
  for (int i = 0; i < 100000; i++) {
    const double v[3] = {i, -i, 0.5 * i};
    GRAN_ASSERT_OK(gran_particles_add(&p, v, i % 5, NULL));
    p.r[3 * i] = 2.0 * i;
    p.t_last[i] = 3.0 * i;
    p.mass[i] = 4.0 * i;
    if (p.capacity != cap) {
      ngrow++;
      cap = p.capacity;
    }
  }
  assert_true(ngrow <= 14); /* 16 * 2^13 > 10^5: doubling, O(1) amortised */
  for (int i = 0; i < 100000; i++) {
    assert_true(p.v[3 * i] == i && p.v[3 * i + 1] == -i && p.v[3 * i + 2] == 0.5 * i);
    assert_int_equal(p.species[i], i % 5);
    assert_true(p.r[3 * i] == 2.0 * i && p.t_last[i] == 3.0 * i && p.mass[i] == 4.0 * i);
  }
  /* reserve grows, keeps contents, never shrinks */
  GRAN_ASSERT_OK(gran_particles_reserve(&p, 300000));
  assert_int_equal(p.capacity, 300000);
  GRAN_ASSERT_OK(gran_particles_reserve(&p, 10));
  assert_int_equal(p.capacity, 300000);
  assert_int_equal(p.n, 100000);
  assert_true(p.v[3 * 99999] == 99999 && p.mass[99999] == 4.0 * 99999);
  GRAN_ASSERT_OK(gran_particles_free(&p));
}

static void test_swap_remove_moves_last(void **state) {
  (void)state;
  gran_particles p;
  GRAN_ASSERT_OK(gran_particles_init(&p, 4, GRAN_PARTICLES_DISPLACEMENT | GRAN_PARTICLES_POSITION | GRAN_PARTICLES_MASS));
  for (int i = 0; i < 4; i++) {
    const double v[3] = {10.0 * i, 10.0 * i + 1, 10.0 * i + 2};
    GRAN_ASSERT_OK(gran_particles_add(&p, v, 100 + i, NULL));
    for (int d = 0; d < 3; d++) {
      p.r[3 * i + d] = 20.0 * i + d;
      p.x[3 * i + d] = 30.0 * i + d;
    }
    p.t_last[i] = 40.0 * i;
    p.mass[i] = 50.0 * i;
  }
  GRAN_ASSERT_OK(gran_particles_swap_remove(&p, 1)); /* particle 3 moves into slot 1 */
  assert_int_equal(p.n, 3);
  for (int d = 0; d < 3; d++) {
    assert_true(p.v[3 + d] == 30.0 + d);
    assert_true(p.r[3 + d] == 60.0 + d);
    assert_true(p.x[3 + d] == 90.0 + d);
  }
  assert_int_equal(p.species[1], 103);
  assert_true(p.t_last[1] == 120.0 && p.mass[1] == 150.0);
  assert_true(p.v[0] == 0.0 && p.v[6] == 20.0); /* others untouched */
  GRAN_ASSERT_OK(gran_particles_swap_remove(&p, 2)); /* the last one: just shrinks */
  assert_int_equal(p.n, 2);
  assert_true(p.v[3] == 30.0);
  GRAN_ASSERT_OK(gran_particles_swap_remove(&p, 0));
  GRAN_ASSERT_OK(gran_particles_swap_remove(&p, 0));
  assert_int_equal(p.n, 0);
  GRAN_ASSERT_ERR(gran_particles_swap_remove(&p, 0), GRAN_ERR_RANGE);
  GRAN_ASSERT_OK(gran_particles_free(&p));
}

static void test_memory(void **state) {
  (void)state;
  gran_particles p;
  int64_t bytes = -1;
  const struct {
    int flags;
    int64_t per;
  } cases[] = {{0, 28},                                              /* 24 v + 4 species */
               {GRAN_PARTICLES_DISPLACEMENT, 60},                    /* + 24 r + 8 t_last */
               {GRAN_PARTICLES_POSITION, 52},                        /* + 24 x */
               {GRAN_PARTICLES_MASS, 36},                            /* + 8 mass */
               {GRAN_PARTICLES_DISPLACEMENT | GRAN_PARTICLES_POSITION | GRAN_PARTICLES_MASS, 92}};
  for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
    GRAN_ASSERT_OK(gran_particles_init(&p, 1000, cases[c].flags));
    GRAN_ASSERT_OK(gran_particles_memory(&p, &bytes));
    assert_int_equal(bytes, 1000 * cases[c].per);
    if (!(cases[c].flags & GRAN_PARTICLES_DISPLACEMENT)) {
      assert_null(p.r);
      assert_null(p.t_last);
    }
    if (!(cases[c].flags & GRAN_PARTICLES_POSITION)) assert_null(p.x);
    if (!(cases[c].flags & GRAN_PARTICLES_MASS)) assert_null(p.mass);
    GRAN_ASSERT_OK(gran_particles_free(&p));
  }
  GRAN_ASSERT_OK(gran_particles_init(&p, 0, 0));
  GRAN_ASSERT_OK(gran_particles_memory(&p, &bytes));
  assert_int_equal(bytes, 0);
  GRAN_ASSERT_OK(gran_particles_free(&p));
}

static void test_errors(void **state) {
  (void)state;
  gran_particles p, z;
  const double v[3] = {1, 2, 3}, vnan[3] = {1, NAN, 3};
  int64_t b;
  GRAN_ASSERT_ERR(gran_particles_init(NULL, 10, 0), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_init(&p, -1, 0), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'capacity'"));
  GRAN_ASSERT_ERR(gran_particles_init(&p, 10, 8), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'flags'"));
  GRAN_ASSERT_ERR(gran_particles_init(&p, 10, -1), GRAN_ERR_ARG);

  GRAN_ASSERT_ERR(gran_particles_reserve(NULL, 10), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_add(NULL, v, 0, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_swap_remove(NULL, 0), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_memory(NULL, &b), GRAN_ERR_ARG);

  /* a struct in an impossible state (n > capacity) */
  memset(&z, 0, sizeof z);
  z.n = 5;
  GRAN_ASSERT_ERR(gran_particles_add(&z, v, 0, NULL), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_particles_memory(&z, &b), GRAN_ERR_STATE);

  GRAN_ASSERT_OK(gran_particles_init(&p, 2, GRAN_PARTICLES_MASS));
  GRAN_ASSERT_ERR(gran_particles_reserve(&p, -3), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_add(&p, NULL, 0, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_add(&p, vnan, 0, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_particles_add(&p, v, -1, NULL), GRAN_ERR_ARG);
  assert_int_equal(p.n, 0); /* nothing added by failed calls */
  GRAN_ASSERT_OK(gran_particles_add(&p, v, 0, NULL));
  GRAN_ASSERT_ERR(gran_particles_swap_remove(&p, 1), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_particles_swap_remove(&p, -1), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_particles_memory(&p, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_particles_free(&p));
  assert_null(p.v);
  assert_null(p.mass);
  assert_int_equal(p.n, 0);
  assert_int_equal(p.capacity, 0);
  GRAN_ASSERT_OK(gran_particles_free(&p)); /* twice */
  GRAN_ASSERT_OK(gran_particles_free(NULL));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_against_reference),
      cmocka_unit_test(test_growth_keeps_contents),
      cmocka_unit_test(test_swap_remove_moves_last),
      cmocka_unit_test(test_memory),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests_name("t301-particles", tests, NULL, NULL);
}
