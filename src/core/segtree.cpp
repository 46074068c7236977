/* segtree.cpp - sum tree over m nonnegative weights: O(log m) update and O(log m) sampling.
 *
 * Layout: node[1] is the root, node[i] = node[2i] + node[2i+1], leaf j is node[base + j] with base
 * the smallest power of two >= m; leaves m..base-1 stay 0. Every internal node is always
 * recomputed from its two children (never incremented by a difference), so after any sequence of
 * updates the array is bit-identical to a fresh build over the same leaves: rounding cannot
 * accumulate, and `nupdate` only reports how many updates happened since the last rebuild.
 */
#include "granary_impl.h"

namespace {

int check_tree(const gran_segtree *t) {
  GRAN_CHECK_PTR(t);
  GRAN_CHECK(t->node != nullptr && t->m >= 1 && t->base >= t->m, GRAN_ERR_STATE,
             "segment tree 't' is not initialised (call gran_segtree_init)");
  return GRAN_SUCCESS;
}

/* i < 0: a scalar argument named `name`; else element i of array `name`. */
int check_weight(double w, const char *name, int64_t i) {
  if (std::isfinite(w) && w >= 0.0) return GRAN_SUCCESS;
  if (i < 0) return GRAN_ERROR(GRAN_ERR_ARG, "weight '%s' = %g is negative or not finite", name, w);
  return GRAN_ERROR(GRAN_ERR_ARG, "weight %s[" GRAN_I64_FMT "] = %g is negative or not finite", name, i, w);
}

/* Recompute every internal node from its children, bottom up: O(base). */
void build_internal(gran_segtree *t) {
  double *node = t->node;
  for (int64_t i = t->base - 1; i >= 1; i--) node[i] = node[2 * i] + node[2 * i + 1];
}

}  // namespace

/** @brief Build the tree over m >= 1 weights in O(m). Overwrites *t without freeing it: free a
 *  tree before initialising it again.
 *  @param[out] t tree  @param[in] m number of leaves  @param[in] w m weights >= 0, or NULL: all 0 */
GRAN_EXTERN int gran_segtree_init(gran_segtree *t, int64_t m, const double *w) {
  GRAN_CHECK_PTR(t);
  GRAN_CHECK(m >= 1, GRAN_ERR_ARG, "argument 'm' = " GRAN_I64_FMT " must be >= 1", m);
  GRAN_CHECK(m <= (INT64_C(1) << 60), GRAN_ERR_ARG, "argument 'm' = " GRAN_I64_FMT " is too large", m);
  if (w)
    for (int64_t i = 0; i < m; i++) GRAN_CALL(check_weight(w[i], "w", i));
  GRAN_TRY {
    int64_t base = 1;
    while (base < m) base *= 2;
    double *node = gran_calloc<double>(2 * base);
    GRAN_CHECK(node != nullptr, GRAN_ERR_NOMEM, "cannot allocate " GRAN_I64_FMT " tree nodes", 2 * base);
    if (w) std::memcpy(node + base, w, sizeof(double) * (size_t)m);
    t->m = m;
    t->base = base;
    t->nupdate = 0;
    t->node = node;
    build_internal(t);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Release the nodes and zero the struct; NULL-safe (t == NULL or never initialised). */
GRAN_EXTERN int gran_segtree_free(gran_segtree *t) {
  if (!t) return GRAN_SUCCESS;
  std::free(t->node);
  t->node = nullptr;
  t->m = t->base = t->nupdate = 0;
  return GRAN_SUCCESS;
}

/** @brief Set weight i to w >= 0 and recompute its ancestors: O(log m). */
GRAN_EXTERN int gran_segtree_set(gran_segtree *t, int64_t i, double w) {
  GRAN_CALL(check_tree(t));
  GRAN_CHECK(i >= 0 && i < t->m, GRAN_ERR_RANGE, "index 'i' = " GRAN_I64_FMT " outside [0, " GRAN_I64_FMT ")",
             i, t->m);
  GRAN_CALL(check_weight(w, "w", -1));
  gran::segtree_set(t, i, w);
  return GRAN_SUCCESS;
}

/** @brief Set n weights w[k] at leaves idx[k] (a repeated index takes its last value), then
 *  recompute the affected ancestors level by level: O(n log(m/n) + n), never more than one O(m)
 *  rebuild. All arguments are checked before anything changes. */
GRAN_EXTERN int gran_segtree_set_batch(gran_segtree *t, int64_t n, const int64_t *idx, const double *w) {
  GRAN_CALL(check_tree(t));
  GRAN_CHECK(n >= 0, GRAN_ERR_ARG, "argument 'n' is negative (" GRAN_I64_FMT ")", n);
  if (n == 0) return GRAN_SUCCESS;
  GRAN_CHECK_PTR(idx);
  GRAN_CHECK_PTR(w);
  for (int64_t k = 0; k < n; k++) {
    GRAN_CHECK(idx[k] >= 0 && idx[k] < t->m, GRAN_ERR_RANGE,
               "idx[" GRAN_I64_FMT "] = " GRAN_I64_FMT " outside [0, " GRAN_I64_FMT ")", k, idx[k], t->m);
    GRAN_CALL(check_weight(w[k], "w", k));
  }
  double *node = t->node;
  const int64_t base = t->base;
  for (int64_t k = 0; k < n; k++) node[base + idx[k]] = w[k];
  /* Level by level, bottom up: at shift s the affected nodes are (base + idx[k]) >> s. A node listed
   * twice is simply recomputed twice (same value), so no sorting or buffer is needed; once a level
   * has no more nodes than the batch, recomputing that whole level and all above is cheaper. */
  for (int64_t s = 1, width = base / 2; width >= 1; s++, width /= 2) {
    if (width <= n) {
      for (int64_t i = 2 * width - 1; i >= 1; i--) node[i] = node[2 * i] + node[2 * i + 1];
      break;
    }
    for (int64_t k = 0; k < n; k++) {
      const int64_t i = (base + idx[k]) >> s;
      node[i] = node[2 * i] + node[2 * i + 1];
    }
  }
  t->nupdate += n;
  return GRAN_SUCCESS;
}

/** @brief Weight of leaf i. */
GRAN_EXTERN int gran_segtree_get(const gran_segtree *t, int64_t i, double *w) {
  GRAN_CALL(check_tree(t));
  GRAN_CHECK_PTR(w);
  GRAN_CHECK(i >= 0 && i < t->m, GRAN_ERR_RANGE, "index 'i' = " GRAN_I64_FMT " outside [0, " GRAN_I64_FMT ")",
             i, t->m);
  *w = t->node[t->base + i];
  return GRAN_SUCCESS;
}

/** @brief Sum of all weights (the root), O(1). */
GRAN_EXTERN int gran_segtree_total(const gran_segtree *t, double *total) {
  GRAN_CALL(check_tree(t));
  GRAN_CHECK_PTR(total);
  *total = t->node[1];
  return GRAN_SUCCESS;
}

/** @brief Leaf index with probability w_i / total from one uniform u in [0,1), O(log m). A
 *  zero-weight leaf is never returned, whatever u (including 0 and nextafter(1, 0)).
 *  @return GRAN_ERR_EMPTY when all weights are 0; GRAN_ERR_NUMERIC when the total overflowed. */
GRAN_EXTERN int gran_segtree_sample(const gran_segtree *t, double u, int64_t *index) {
  GRAN_CALL(check_tree(t));
  GRAN_CHECK_PTR(index);
  GRAN_CHECK(u >= 0.0 && u < 1.0, GRAN_ERR_ARG, "argument 'u' = %g outside [0, 1)", u);
  const double total = t->node[1];
  GRAN_CHECK(total > 0.0, GRAN_ERR_EMPTY, "all " GRAN_I64_FMT " weights are zero", t->m);
  GRAN_CHECK(std::isfinite(total), GRAN_ERR_NUMERIC, "sum of the weights overflowed (%g)", total);
  *index = gran::segtree_sample(t, u);
  return GRAN_SUCCESS;
}

/** @brief Recompute every internal node from the leaves (O(m)) and reset nupdate. Because updates
 *  already recompute parents from children, this changes no bit of a consistent tree; it repairs
 *  a tree whose leaves were written directly through t->node. */
GRAN_EXTERN int gran_segtree_rebuild(gran_segtree *t) {
  GRAN_CALL(check_tree(t));
  for (int64_t i = 0; i < t->m; i++) {
    const double w = t->node[t->base + i];
    GRAN_CHECK(std::isfinite(w) && w >= 0.0, GRAN_ERR_DOMAIN,
               "leaf " GRAN_I64_FMT " holds %g: weights must be finite and >= 0", i, w);
  }
  build_internal(t);
  t->nupdate = 0;
  return GRAN_SUCCESS;
}
