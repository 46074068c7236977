/* particles.cpp - structure-of-arrays particle storage: O(1) amortised add, O(1) swap-remove.
 *
 * Always allocated: v (3 doubles, interleaved) and species (int32): 28 bytes per slot.
 * GRAN_PARTICLES_DISPLACEMENT adds r (3 doubles) and t_last (1 double): +32 bytes;
 * GRAN_PARTICLES_POSITION adds x (3 doubles): +24; GRAN_PARTICLES_MASS adds mass: +8.
 * An array whose flag is off is NULL and costs nothing.
 */
#include "granary_impl.h"

#include <cstdlib>

namespace {

const int kAllFlags = GRAN_PARTICLES_DISPLACEMENT | GRAN_PARTICLES_POSITION | GRAN_PARTICLES_MASS;

/* One table for every array: pointer, doubles/ints per particle, element size, flag (0: always). */
struct ArrayRef {
  void **ptr;
  int64_t per;
  size_t elem;
  int flag;
};

int arrays(gran_particles *p, ArrayRef out[6]) {
  out[0] = {(void **)&p->v, 3, sizeof(double), 0};
  out[1] = {(void **)&p->species, 1, sizeof(int32_t), 0};
  out[2] = {(void **)&p->r, 3, sizeof(double), GRAN_PARTICLES_DISPLACEMENT};
  out[3] = {(void **)&p->t_last, 1, sizeof(double), GRAN_PARTICLES_DISPLACEMENT};
  out[4] = {(void **)&p->x, 3, sizeof(double), GRAN_PARTICLES_POSITION};
  out[5] = {(void **)&p->mass, 1, sizeof(double), GRAN_PARTICLES_MASS};
  return 6;
}

bool active(const ArrayRef &a, int flags) { return a.flag == 0 || (flags & a.flag); }

int bytes_per_particle(int flags) {
  gran_particles dummy{};
  ArrayRef a[6];
  const int na = arrays(&dummy, a);
  int bytes = 0;
  for (int k = 0; k < na; k++)
    if (active(a[k], flags)) bytes += (int)(a[k].per * (int64_t)a[k].elem);
  return bytes;
}

int check_particles(const gran_particles *p) {
  GRAN_CHECK_PTR(p);
  GRAN_CHECK(p->n >= 0 && p->capacity >= p->n && (p->flags & ~kAllFlags) == 0 &&
                 (p->capacity == 0 || (p->v && p->species)),
             GRAN_ERR_STATE, "particle arrays 'p' are not initialised (call gran_particles_init)");
  return GRAN_SUCCESS;
}

/* Grow every allocated array to `capacity` slots (contents kept). */
int grow(gran_particles *p, int64_t capacity) {
  GRAN_CHECK(capacity <= (INT64_C(1) << 58), GRAN_ERR_ARG, "capacity " GRAN_I64_FMT " is too large", capacity);
  ArrayRef a[6];
  const int na = arrays(p, a);
  for (int k = 0; k < na; k++) {
    if (!active(a[k], p->flags)) continue;
    void *q = std::realloc(*a[k].ptr, (size_t)(capacity * a[k].per) * a[k].elem);
    /* on failure the old block stays valid and p->capacity unchanged: the struct stays usable */
    GRAN_CHECK(q != nullptr, GRAN_ERR_NOMEM, "cannot grow particle arrays to " GRAN_I64_FMT " slots", capacity);
    *a[k].ptr = q;
  }
  p->capacity = capacity;
  return GRAN_SUCCESS;
}

}  // namespace

/** @brief Empty particle set with room for `capacity` particles; arrays whose flag is not set stay
 *  NULL. Overwrites *p without freeing it.
 *  @param[out] p  @param[in] capacity >= 0  @param[in] flags OR of gran_particle_flags */
GRAN_EXTERN int gran_particles_init(gran_particles *p, int64_t capacity, int flags) {
  GRAN_CHECK_PTR(p);
  GRAN_CHECK(capacity >= 0, GRAN_ERR_ARG, "argument 'capacity' is negative (" GRAN_I64_FMT ")", capacity);
  GRAN_CHECK((flags & ~kAllFlags) == 0, GRAN_ERR_ARG, "argument 'flags' = %d has unknown bits", flags);
  *p = gran_particles{};
  p->flags = flags;
  if (capacity == 0) return GRAN_SUCCESS;
  const int ierr = grow(p, capacity);
  if (ierr != GRAN_SUCCESS) gran_particles_free(p);
  return ierr;
}

/** @brief Release every array and zero the struct; NULL-safe. */
GRAN_EXTERN int gran_particles_free(gran_particles *p) {
  if (!p) return GRAN_SUCCESS;
  ArrayRef a[6];
  const int na = arrays(p, a);
  for (int k = 0; k < na; k++) std::free(*a[k].ptr);
  *p = gran_particles{};
  return GRAN_SUCCESS;
}

/** @brief Make room for at least `capacity` particles (never shrinks; contents kept). */
GRAN_EXTERN int gran_particles_reserve(gran_particles *p, int64_t capacity) {
  GRAN_CALL(check_particles(p));
  GRAN_CHECK(capacity >= 0, GRAN_ERR_ARG, "argument 'capacity' is negative (" GRAN_I64_FMT ")", capacity);
  if (capacity <= p->capacity) return GRAN_SUCCESS;
  return grow(p, capacity);
}

/** @brief Append a particle with velocity v and species `species`, O(1) amortised (capacity
 *  doubles when full); its optional arrays are zeroed.
 *  @param[out] index its slot (may be NULL) */
GRAN_EXTERN int gran_particles_add(gran_particles *p, const double v[3], int32_t species, int64_t *index) {
  GRAN_CALL(check_particles(p));
  GRAN_CHECK_PTR(v);
  GRAN_CHECK(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]), GRAN_ERR_ARG,
             "velocity 'v' = (%g, %g, %g) is not finite", v[0], v[1], v[2]);
  GRAN_CHECK(species >= 0, GRAN_ERR_ARG, "argument 'species' is negative (%d)", (int)species);
  if (p->n == p->capacity) GRAN_CALL(grow(p, p->capacity < 8 ? 16 : 2 * p->capacity));
  const int64_t i = p->n++;
  p->v[3 * i] = v[0];
  p->v[3 * i + 1] = v[1];
  p->v[3 * i + 2] = v[2];
  p->species[i] = species;
  if (p->r) p->r[3 * i] = p->r[3 * i + 1] = p->r[3 * i + 2] = 0.0;
  if (p->t_last) p->t_last[i] = 0.0;
  if (p->x) p->x[3 * i] = p->x[3 * i + 1] = p->x[3 * i + 2] = 0.0;
  if (p->mass) p->mass[i] = 0.0;
  if (index) *index = i;
  return GRAN_SUCCESS;
}

/** @brief Remove particle i in O(1): the last particle moves into slot i in every allocated array
 *  (so indices of other particles stay valid except the last one's). */
GRAN_EXTERN int gran_particles_swap_remove(gran_particles *p, int64_t i) {
  GRAN_CALL(check_particles(p));
  GRAN_CHECK(i >= 0 && i < p->n, GRAN_ERR_RANGE, "index 'i' = " GRAN_I64_FMT " outside [0, " GRAN_I64_FMT ")",
             i, p->n);
  const int64_t last = --p->n;
  if (i == last) return GRAN_SUCCESS;
  ArrayRef a[6];
  const int na = arrays(p, a);
  for (int k = 0; k < na; k++) {
    if (!*a[k].ptr) continue;
    char *base = static_cast<char *>(*a[k].ptr);
    const size_t sz = (size_t)a[k].per * a[k].elem;
    std::memcpy(base + (size_t)i * sz, base + (size_t)last * sz, sz);
  }
  return GRAN_SUCCESS;
}

/** @brief Bytes held by the arrays: capacity times the bytes per particle of the allocated arrays
 *  (28 for v + species, 60 with GRAN_PARTICLES_DISPLACEMENT, +24 position, +8 mass). */
GRAN_EXTERN int gran_particles_memory(const gran_particles *p, int64_t *bytes) {
  GRAN_CALL(check_particles(p));
  GRAN_CHECK_PTR(bytes);
  *bytes = p->capacity * bytes_per_particle(p->flags);
  return GRAN_SUCCESS;
}
