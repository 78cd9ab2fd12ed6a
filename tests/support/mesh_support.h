/* Meshes, brute-force geometry and mesh2sdf's dense output, for the
 * converter's tests: a mesh as arrays, OBJ reading and OFF writing, the exact
 * winding number and distance by brute force over every triangle, and a
 * grid read back through mesh2sdf's --npy output and its JSON sidecar. */
#ifndef SDFT_TEST_MESH_SUPPORT_H
#define SDFT_TEST_MESH_SUPPORT_H

typedef struct mesh {
    double *v; /* 3 per vertex */
    int *t;    /* 3 per triangle */
    int nv, nt, cap_v, cap_t;
} mesh;

void mesh_vertex(mesh *m, double x, double y, double z);
void mesh_triangle(mesh *m, int a, int b, int c);
void mesh_free(mesh *m);
/* Four slivers around the unit cube centred at the origin, exact in float:
 * two thinner than the distance formula's threshold for a reliable normal
 * (1e-8 of the longest edge: they count as their edges) and two just above
 * it (their normal from an ill-conditioned cross product), flat (at z =
 * +-0.75) and tilted (beside x = +-0.875). */
void mesh_add_slivers(mesh *m);
/* Reads the v and f lines of an OBJ (v, v/t, v/t/n, v//n, negative
 * indices); polygons become fans. */
int read_obj(const char *path, mesh *m);
void write_off(const char *path, const mesh *m);

double dot3(const double *a, const double *b);
/* Squared distance from p to segment ab, to triangle abc. */
double seg_dist2(const double *p, const double *a, const double *b);
double tri_dist2(const double *p, const double *a, const double *b, const double *c);
/* Generalized winding number by brute force (Van Oosterom-Strackee). */
double winding(const mesh *m, const double *q);
/* Brute force: the distance from p to the nearest triangle of m. */
double mesh_distance(const mesh *m, const double *p);
double mesh_sdf(const mesh *m, const double *p);

typedef struct dense {
    int n[3];
    double origin[3], h;
    float *data; /* n[0]*n[1]*n[2], C order */
} dense;

double json_number(const char *json, const char *key, int index);
void read_dense(const char *npy, dense *g);
float dense_at(const dense *g, int i, int j, int k);
void dense_point(const dense *g, int i, int j, int k, double *p);
/* Runs mesh2sdf on `in` with extra flags, writing NAME.vdb and NAME.npy in
 * the test folder, and reads the dense grid back. */
void convert(const char *in, const char *name, const char *flags, dense *g);

#endif
