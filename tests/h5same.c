/* h5same.c - the test scripts' comparison of two HDF5 files (tests/t611-mpi.sh, tests/t615-mpi-run-split.sh):
 * `h5same A B` exits 0 when both hold the same datasets, each with the same shape, type and bytes
 * (attributes, which hold HDF5's timestamps and the run's provenance, are not compared). */
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#if H5_VERSION_GE(1, 12, 0)
#define INFO H5O_info2_t
#define VISIT(f, cb) H5Ovisit3(f, H5_INDEX_NAME, H5_ITER_INC, cb, NULL, H5O_INFO_BASIC)
#else
#define INFO H5O_info_t
#define VISIT(f, cb) H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_INC, cb, NULL, H5O_INFO_BASIC)
#endif
static hid_t other; static int bad = 0, n = 0; static const char *oname;
static herr_t visit(hid_t loc, const char *name, const INFO *info, void *op) {
  (void)op;
  if (info->type != H5O_TYPE_DATASET) return 0;
  if (H5Lexists(other, name, H5P_DEFAULT) <= 0) { printf("  %s: missing in %s\n", name, oname); bad = 1; return 0; }
  hid_t a = H5Dopen2(loc, name, H5P_DEFAULT), b = H5Dopen2(other, name, H5P_DEFAULT);
  hid_t ta = H5Dget_type(a), tb = H5Dget_type(b), na = H5Tget_native_type(ta, H5T_DIR_DEFAULT);
  hssize_t ea = H5Sget_simple_extent_npoints(H5Dget_space(a)), eb = H5Sget_simple_extent_npoints(H5Dget_space(b));
  size_t sz = H5Tget_size(na);
  if (ea != eb || H5Tequal(ta, tb) <= 0) { printf("  %s: shape or type differs\n", name); bad = 1; return 0; }
  char *x = malloc((size_t)ea * sz + 1), *y = malloc((size_t)ea * sz + 1);
  if (ea > 0 && (H5Dread(a, na, H5S_ALL, H5S_ALL, H5P_DEFAULT, x) < 0 || H5Dread(b, na, H5S_ALL, H5S_ALL, H5P_DEFAULT, y) < 0)) {
    printf("  %s: unreadable (%s)\n", name, H5Tget_class(ta) == H5T_STRING ? "string" : "?"); bad = 1;
  } else if (ea > 0 && memcmp(x, y, (size_t)ea * sz) != 0) { printf("  %s: values differ\n", name); bad = 1; }
  n++;
  free(x); free(y); H5Tclose(na); H5Tclose(ta); H5Tclose(tb); H5Dclose(a); H5Dclose(b);
  return 0;
}
int main(int argc, char **argv) {
  if (argc != 3) return 2;
  hid_t f = H5Fopen(argv[1], H5F_ACC_RDONLY, H5P_DEFAULT), g = H5Fopen(argv[2], H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0 || g < 0) { printf("cannot open %s or %s\n", argv[1], argv[2]); return 1; }
  other = g; oname = argv[2];
  VISIT(f, visit);
  int na = n; n = 0; other = f; oname = argv[1];
  VISIT(g, visit); /* nothing extra in B */
  printf("%s %s vs %s: %d datasets %s\n", bad ? "FAIL:" : "ok:", argv[1], argv[2], na, bad ? "DIFFER" : "bit for bit equal");
  return bad || na == 0 || n != na;
}
