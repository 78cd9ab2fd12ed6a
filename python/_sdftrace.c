/* sdftrace — the Python extension _sdftrace: sdftrace/mesh.h, grid.h,
 * vdb.h and render.h on numpy arrays, through the CPython and NumPy C APIs.
 * The package sdftrace (python/sdftrace/__init__.py) is what users import;
 * it documents every call. Arrays are made here first and filled by the
 * library with the GIL released, so results are never copied; inputs are
 * read in place where their layout allows. Errors raise ValueError
 * (SDFT_EINVAL), OSError (SDFT_EIO), sdftrace.Canceled (SDFT_ECANCELED),
 * MemoryError (SDFT_ENOMEM) or RuntimeError, with the library's line. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <numpy/arrayobject.h>

#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "parse.h" /* src/common: the names of a choice */
#include "sdftrace/grid.h"
#include "sdftrace/mesh.h"
#include "sdftrace/render.h"
#include "sdftrace/scene.h"
#include "sdftrace/vdb.h"

#define MSG_LEN 512

/* sdftrace.Canceled: a progress callable asked to stop (SDFT_ECANCELED). */
static PyObject *Canceled;

/* ---- errors --------------------------------------------------------- */

static PyObject *raise_error(sdft_error e, const char *msg)
{
    PyObject *type = PyExc_RuntimeError;
    switch (e) {
    case SDFT_EINVAL:
        type = PyExc_ValueError;
        break;
    case SDFT_EIO:
    case SDFT_EFORMAT:
    case SDFT_ENOTFOUND:
    case SDFT_ENOTSCALAR:
        type = e == SDFT_EIO ? PyExc_OSError : PyExc_ValueError;
        break;
    case SDFT_ENOMEM:
        type = PyExc_MemoryError;
        break;
    case SDFT_ECANCELED:
        type = Canceled;
        break;
    default:
        break;
    }
    PyErr_SetString(type, msg && *msg ? msg : sdft_error_name(e));
    return NULL;
}

/* ---- arrays --------------------------------------------------------- */

/* obj as an aligned (n, 3) float32 or float64 array, in place when it is
 * one already (any strides), into *pts; a new reference, or NULL with an
 * exception set. */
static PyArrayObject *points_of(PyObject *obj, sdft_mesh_points *pts)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (!a)
        return NULL;
    const int type = PyArray_TYPE(a);
    if (type != NPY_FLOAT32 && type != NPY_FLOAT64) {
        Py_SETREF(a, (PyArrayObject *)PyArray_FROMANY((PyObject *)a, NPY_FLOAT64, 0, 0, NPY_ARRAY_ALIGNED));
        if (!a)
            return NULL;
    } else if (!PyArray_ISALIGNED(a)) {
        Py_SETREF(a, (PyArrayObject *)PyArray_FROMANY((PyObject *)a, type, 0, 0, NPY_ARRAY_ALIGNED));
        if (!a)
            return NULL;
    }
    if (PyArray_NDIM(a) != 2 || PyArray_DIM(a, 1) != 3) {
        PyErr_SetString(PyExc_ValueError, "points must be an array of shape (n, 3)");
        Py_DECREF(a);
        return NULL;
    }
    pts->data = PyArray_DATA(a);
    pts->type = PyArray_TYPE(a) == NPY_FLOAT32 ? SDFT_MESH_FLOAT32 : SDFT_MESH_FLOAT64;
    pts->count = (size_t)PyArray_DIM(a, 0);
    pts->stride[0] = PyArray_STRIDE(a, 0);
    pts->stride[1] = PyArray_STRIDE(a, 1);
    if (pts->count && pts->stride[0] == 0 && pts->stride[1] == 0)
        pts->stride[1] = PyArray_ITEMSIZE(a); /* a broadcast point: not "packed" */
    return a;
}

/* A new float32 array of `ndim` dims. */
static PyArrayObject *new_floats(int ndim, npy_intp *dims)
{
    return (PyArrayObject *)PyArray_SimpleNew(ndim, dims, NPY_FLOAT32);
}

/* ---- progress: a Python callable told how far a long call is ---------- */

typedef struct {
    PyObject *fn;                       /* callable(done) -> true to stop */
    PyObject *type, *value, *traceback; /* what it raised, for the caller's thread */
} progress_call;

/* The library's sdft_progress_fn: from a worker thread (or the caller's,
 * which releases the GIL first), so it takes the GIL to call fn (when
 * given). An exception from fn stops the call and is kept for the caller,
 * and so does Ctrl-C: Python's signal handlers run here (on the main
 * thread, which in a call from it reports too), so KeyboardInterrupt stops
 * a long conversion at its next report. */
static int call_progress(void *user, float done)
{
    progress_call *p = user;
    PyGILState_STATE g = PyGILState_Ensure();
    int stop = p->type != NULL;
    if (!stop && PyErr_CheckSignals() < 0) {
        PyErr_Fetch(&p->type, &p->value, &p->traceback);
        stop = 1;
    }
    if (!stop && p->fn) {
        PyObject *r = PyObject_CallFunction(p->fn, "d", (double)done);
        if (!r) {
            PyErr_Fetch(&p->type, &p->value, &p->traceback);
            stop = 1;
        } else {
            stop = PyObject_IsTrue(r) > 0;
            Py_DECREF(r);
        }
    }
    PyGILState_Release(g);
    return stop;
}

/* fn (None: no reports, but Ctrl-C still heard) as the library's callback
 * and its user pointer. */
static void progress_of(PyObject *fn, progress_call *p, sdft_progress_fn *cb, void **user)
{
    memset(p, 0, sizeof *p);
    if (fn && fn != Py_None)
        p->fn = fn;
    *cb = call_progress;
    *user = p;
}

/* After the call, with the GIL: raises what fn raised and returns NULL;
 * otherwise raises for e (SDFT_OK: returns `result`). */
static PyObject *progress_result(progress_call *p, sdft_error e, const char *msg, PyObject *result)
{
    if (p->type || e != SDFT_OK)
        Py_XDECREF(result);
    if (p->type) {
        PyErr_Restore(p->type, p->value, p->traceback);
        return NULL;
    }
    return e == SDFT_OK ? result : raise_error(e, msg);
}

/* ---- settings: the library's tables (sdftrace/mesh.h) ----------------- */

static const char *const kind_names[] = {"int", "count", "real", "flag", "choice", "text"};

/* The settings of params struct `of` as a list of dicts, the rows of its
 * table: what the package makes its keywords, defaults and docstrings of. */
static PyObject *settings(PyObject *module, PyObject *arg)
{
    (void)module;
    const long of = PyLong_AsLong(arg);
    if (of == -1 && PyErr_Occurred())
        return NULL;
    size_t n = 0;
    const sdft_mesh_setting *rows = sdft_mesh_settings((sdft_mesh_settings_of)of, &n);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; i++) {
        const sdft_mesh_setting *r = &rows[i];
        PyObject *def = r->count > 1 ? Py_BuildValue("(dd)", r->def[0], r->def[1]) : Py_BuildValue("(d)", r->def[0]);
        PyObject *row =
            def ? Py_BuildValue("{sssssisNsdsdsOsOsOszszszss}", "name", r->name, "kind", kind_names[r->kind], "count",
                                r->count, "default", def, "lo", r->lo, "hi", r->hi, "open_lo",
                                r->flags & SDFT_MESH_SETTING_OPEN_LO ? Py_True : Py_False, "open_hi",
                                r->flags & SDFT_MESH_SETTING_OPEN_HI ? Py_True : Py_False, "automatic_default",
                                r->flags & SDFT_MESH_SETTING_AUTO ? Py_True : Py_False, "choices", r->choices,
                                "automatic", r->automatic, "value", r->value, "doc", r->doc)
                : NULL;
        if (!row)
            Py_CLEAR(list);
        else
            PyList_SET_ITEM(list, (Py_ssize_t)i, row);
    }
    return list;
}

/* One value into row r's member at `at`: 0, or -1 with an exception.
 * Ranges are the library's to check (the call that takes the params). */
static int set_setting(const sdft_mesh_setting *r, char *at, PyObject *v)
{
    switch (r->kind) {
    case SDFT_MESH_SETTING_INT: {
        int overflow = 0;
        const long x = PyLong_AsLongAndOverflow(v, &overflow);
        if (x == -1 && PyErr_Occurred())
            return -1;
        if (overflow || x < INT_MIN || x > INT_MAX) {
            PyErr_Format(PyExc_ValueError, "%s is out of range", r->name);
            return -1;
        }
        const int i = (int)x;
        memcpy(at, &i, sizeof i);
        return 0;
    }
    case SDFT_MESH_SETTING_COUNT: {
        if (!PyLong_Check(v)) {
            PyErr_Format(PyExc_TypeError, "%s must be an integer", r->name);
            return -1;
        }
        const unsigned long long x = PyLong_AsUnsignedLongLong(v);
        if (x == (unsigned long long)-1 && PyErr_Occurred()) {
            PyErr_Clear();
            PyErr_Format(PyExc_ValueError, "%s is out of range", r->name);
            return -1;
        }
        const uint64_t u = x;
        memcpy(at, &u, sizeof u);
        return 0;
    }
    case SDFT_MESH_SETTING_REAL: {
        double x[2];
        if (r->count == 1) {
            x[0] = PyFloat_AsDouble(v);
            if (x[0] == -1.0 && PyErr_Occurred())
                return -1;
        } else if (!PyArg_ParseTuple(v, r->count == 2 ? "dd" : "d", &x[0], &x[1])) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "%s must be %d numbers", r->name, r->count);
            return -1;
        }
        memcpy(at, x, sizeof(double) * (size_t)r->count);
        return 0;
    }
    case SDFT_MESH_SETTING_FLAG: {
        const int on = PyObject_IsTrue(v);
        if (on < 0)
            return -1;
        memcpy(at, &on, sizeof on);
        return 0;
    }
    case SDFT_MESH_SETTING_CHOICE: {
        int i = -1;
        if (PyUnicode_Check(v)) {
            const char *name = PyUnicode_AsUTF8(v);
            if (!name)
                return -1;
            i = parse_list_index(r->choices, name);
            if (i < 0) {
                PyErr_Format(PyExc_ValueError, "%s must be one of: %s (got '%s')", r->name, r->choices, name);
                return -1;
            }
        } else {
            const long x = PyLong_AsLong(v); /* a bool or an int: the value itself */
            if (x == -1 && PyErr_Occurred())
                return -1;
            i = x < INT_MIN || x > INT_MAX ? -1 : (int)x;
        }
        memcpy(at, &i, sizeof i);
        return 0;
    }
    case SDFT_MESH_SETTING_TEXT: {
        const char *text = v == Py_None ? NULL : PyUnicode_AsUTF8(v); /* kept alive by the caller's kwargs */
        if (v != Py_None && !text)
            return -1;
        memcpy(at, &text, sizeof text);
        return 0;
    }
    }
    return 0;
}

/* The members of `params` (a struct of kind `of`) that kw names, each
 * from its value: 0, or -1 with an exception (TypeError for a name that is
 * not a setting). kw may be NULL. */
static int set_settings(sdft_mesh_settings_of of, void *params, PyObject *kw)
{
    size_t n = 0;
    const sdft_mesh_setting *rows = sdft_mesh_settings(of, &n);
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    while (kw && PyDict_Next(kw, &pos, &key, &value)) {
        const char *name = PyUnicode_Check(key) ? PyUnicode_AsUTF8(key) : NULL;
        if (!name)
            return -1;
        size_t i = 0;
        while (i < n && strcmp(rows[i].name, name) != 0)
            i++;
        if (i == n) {
            PyErr_Format(PyExc_TypeError, "unexpected keyword argument '%s'", name);
            return -1;
        }
        if (set_setting(&rows[i], (char *)params + rows[i].offset, value) < 0)
            return -1;
    }
    return 0;
}

/* ---- Mesh ----------------------------------------------------------- */

/* A Python object that owns one of the library's handles: its struct
 * (the handle in `field`), the type's dealloc, which frees the handle, and
 * NAME_wrap(handle), which makes one (or frees the handle and fails). */
#define HANDLE_OBJECT(Name, type, field, release)                                                                      \
    typedef struct {                                                                                                   \
        PyObject_HEAD type *field;                                                                                     \
    } Name##Object;                                                                                                    \
    static PyTypeObject Name##Type;                                                                                    \
    static void Name##_dealloc(Name##Object *self)                                                                     \
    {                                                                                                                  \
        release(self->field);                                                                                          \
        Py_TYPE(self)->tp_free((PyObject *)self);                                                                      \
    }                                                                                                                  \
    static PyObject *Name##_wrap(type *handle)                                                                         \
    {                                                                                                                  \
        Name##Object *o = PyObject_New(Name##Object, &Name##Type);                                                     \
        if (!o) {                                                                                                      \
            release(handle);                                                                                           \
            return NULL;                                                                                               \
        }                                                                                                              \
        o->field = handle;                                                                                             \
        return (PyObject *)o;                                                                                          \
    }

HANDLE_OBJECT(Mesh, sdft_mesh, mesh, sdft_mesh_free)

/* load_mesh(path, **settings): settings of sdft_mesh_params. */
static PyObject *load_mesh(PyObject *module, PyObject *args, PyObject *kw)
{
    (void)module;
    PyObject *path_obj;
    if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path_obj))
        return NULL;
    sdft_mesh_params p = sdft_mesh_params_defaults();
    if (set_settings(SDFT_MESH_SETTINGS_MESH, &p, kw) < 0) {
        Py_DECREF(path_obj);
        return NULL;
    }
    const char *path = PyBytes_AS_STRING(path_obj);
    sdft_mesh *m = NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_load(path, &p, &m, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    Py_DECREF(path_obj);
    return e == SDFT_OK ? Mesh_wrap(m) : raise_error(e, msg);
}

/* faces as int32, uint32 or int64, C order (other integer types become int64). */
static PyArrayObject *faces_of(PyObject *obj, sdft_mesh_dtype *type)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (!a)
        return NULL;
    int t = PyArray_TYPE(a);
    if (!PyArray_ISINTEGER(a)) {
        PyErr_SetString(PyExc_ValueError, "faces must be an integer array of shape (m, 3)");
        Py_DECREF(a);
        return NULL;
    }
    if (t != NPY_INT32 && t != NPY_UINT32 && t != NPY_INT64)
        t = NPY_INT64;
    Py_SETREF(a, (PyArrayObject *)PyArray_FROMANY((PyObject *)a, t, 2, 2, NPY_ARRAY_IN_ARRAY));
    if (!a)
        return NULL;
    *type = t == NPY_INT32 ? SDFT_MESH_INT32 : t == NPY_UINT32 ? SDFT_MESH_UINT32 : SDFT_MESH_INT64;
    return a;
}

static PyArrayObject *vertices_of(PyObject *obj, sdft_mesh_dtype *type)
{
    PyArrayObject *a = (PyArrayObject *)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (!a)
        return NULL;
    const int t = PyArray_TYPE(a) == NPY_FLOAT32 ? NPY_FLOAT32 : NPY_FLOAT64;
    Py_SETREF(a, (PyArrayObject *)PyArray_FROMANY((PyObject *)a, t, 2, 2, NPY_ARRAY_IN_ARRAY));
    if (!a)
        return NULL;
    *type = t == NPY_FLOAT32 ? SDFT_MESH_FLOAT32 : SDFT_MESH_FLOAT64;
    return a;
}

/* mesh_from_arrays(vertices, faces, **settings): settings of sdft_mesh_params. */
static PyObject *mesh_from_arrays(PyObject *module, PyObject *args, PyObject *kw)
{
    (void)module;
    PyObject *vobj, *fobj;
    if (!PyArg_ParseTuple(args, "OO", &vobj, &fobj))
        return NULL;
    sdft_mesh_params p = sdft_mesh_params_defaults();
    if (set_settings(SDFT_MESH_SETTINGS_MESH, &p, kw) < 0)
        return NULL;
    sdft_mesh_dtype vt, ft;
    PyArrayObject *v = vertices_of(vobj, &vt);
    if (!v)
        return NULL;
    PyArrayObject *f = faces_of(fobj, &ft);
    if (!f) {
        Py_DECREF(v);
        return NULL;
    }
    if (PyArray_DIM(v, 1) != 3 || PyArray_DIM(f, 1) != 3) {
        Py_DECREF(v);
        Py_DECREF(f);
        PyErr_SetString(PyExc_ValueError, "vertices must have shape (n, 3) and faces (m, 3)");
        return NULL;
    }
    sdft_mesh *m = NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_from_arrays(PyArray_DATA(v), vt, (size_t)PyArray_DIM(v, 0), PyArray_DATA(f), ft,
                              (size_t)PyArray_DIM(f, 0), &p, &m, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    Py_DECREF(v);
    Py_DECREF(f);
    return e == SDFT_OK ? Mesh_wrap(m) : raise_error(e, msg);
}

/* Distances (and winding numbers) at points: mode 0 distance, 1 winding
 * number, 2 both as a tuple. */
static PyObject *mesh_query(MeshObject *self, PyObject *points, int mode)
{
    sdft_mesh_points pts;
    PyArrayObject *in = points_of(points, &pts);
    if (!in)
        return NULL;
    npy_intp n = (npy_intp)pts.count;
    PyArrayObject *d = mode != 1 ? new_floats(1, &n) : NULL;
    PyArrayObject *w = mode != 0 ? new_floats(1, &n) : NULL;
    if ((mode != 1 && !d) || (mode != 0 && !w)) {
        Py_XDECREF(d);
        Py_XDECREF(w);
        Py_DECREF(in);
        return NULL;
    }
    float *dp = d ? (float *)PyArray_DATA(d) : NULL, *wp = w ? (float *)PyArray_DATA(w) : NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    progress_call pc; /* no callable: Ctrl-C alone */
    sdft_mesh_query_params q = sdft_mesh_query_params_defaults();
    progress_of(NULL, &pc, &q.progress, &q.progress_user);
    PyThreadState *ts = PyEval_SaveThread();
    e = mode == 1 ? sdft_mesh_winding_number(self->mesh, &pts, wp, &q, msg, sizeof msg)
                  : sdft_mesh_signed_distance(self->mesh, &pts, dp, wp, &q, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    Py_DECREF(in);
    if (pc.type || e != SDFT_OK) {
        Py_XDECREF(d);
        Py_XDECREF(w);
        return progress_result(&pc, e, msg, NULL);
    }
    if (mode == 2)
        return Py_BuildValue("(NN)", d, w);
    return (PyObject *)(d ? d : w);
}

static PyObject *mesh_signed_distance(MeshObject *self, PyObject *args, PyObject *kw)
{
    static char *names[] = {"points", "winding", NULL};
    PyObject *points;
    int winding = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|p", names, &points, &winding))
        return NULL;
    return mesh_query(self, points, winding ? 2 : 0);
}

static PyObject *mesh_winding_number(MeshObject *self, PyObject *points) { return mesh_query(self, points, 1); }

/* samples(n, progress=None, **settings): settings of sdft_mesh_sample_params. */
static PyObject *mesh_samples(MeshObject *self, PyObject *args, PyObject *kw)
{
    Py_ssize_t n;
    PyObject *progress = Py_None;
    if (!PyArg_ParseTuple(args, "n|O", &n, &progress))
        return NULL;
    sdft_mesh_sample_params p = sdft_mesh_sample_params_defaults();
    if (set_settings(SDFT_MESH_SETTINGS_SAMPLES, &p, kw) < 0)
        return NULL;
    progress_call pc;
    progress_of(progress, &pc, &p.progress, &p.progress_user);
    if (n < 1)
        return raise_error(SDFT_EINVAL, "n must be at least 1");
    p.count = (uint64_t)n;
    npy_intp dims[2] = {n, 4};
    PyArrayObject *rows = new_floats(2, dims);
    if (!rows)
        return NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_samples(self->mesh, &p, (float *)PyArray_DATA(rows), (size_t)n * 4, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    return progress_result(&pc, e, msg, (PyObject *)rows);
}

static PyObject *mesh_info(MeshObject *self, PyObject *unused)
{
    (void)unused;
    sdft_mesh_health i;
    sdft_mesh_frame f;
    char msg[MSG_LEN] = "";
    sdft_error e = sdft_mesh_get_health(self->mesh, &i, msg, sizeof msg);
    if (e == SDFT_OK)
        e = sdft_mesh_get_frame(self->mesh, &f, msg, sizeof msg);
    if (e != SDFT_OK)
        return raise_error(e, msg);
    /* The health report and the frame, member by member, and the warnings. */
    char warnings[4096];
    sdft_mesh_warnings(self->mesh, warnings, sizeof warnings);
    return Py_BuildValue("{sKsKsKsKsKsKsKsOsOsKsKsKsKsKsKsKsKsKsdsss(ddd)s(ddd)s(ddd)sdsO}", "vertices", i.vertices,
                         "faces", i.faces, "triangles", i.triangles, "degenerate_faces", i.degenerate_faces,
                         "welded_vertices", i.welded_vertices, "boundary_edges", i.boundary_edges, "non_manifold_edges",
                         i.non_manifold_edges, "closed", i.closed ? Py_True : Py_False, "oriented",
                         i.oriented ? Py_True : Py_False, "duplicate_faces", i.duplicate_faces, "patches", i.patches,
                         "non_orientable_patches", i.non_orientable_patches, "reoriented_faces", i.reoriented_faces,
                         "outward_patches", i.outward_patches, "cavity_patches", i.cavity_patches, "ambiguous_patches",
                         i.ambiguous_patches, "skipped_faces", i.skipped_faces, "evidence_patches", i.evidence_patches,
                         "ambiguous_area", i.ambiguous_area, "warnings", warnings, "lo", f.lo[0], f.lo[1], f.lo[2],
                         "hi", f.hi[0], f.hi[1], f.hi[2], "centre", f.centre[0], f.centre[1], f.centre[2], "radius",
                         f.radius, "normalized", f.normalized ? Py_True : Py_False);
}

static PyObject *MeshGrid_wrap(sdft_mesh_grid *handle);

/* to_grid(progress=None, **settings): settings of sdft_mesh_grid_params. */
static PyObject *mesh_to_grid(MeshObject *self, PyObject *args, PyObject *kw)
{
    PyObject *progress = Py_None;
    if (!PyArg_ParseTuple(args, "|O", &progress))
        return NULL;
    sdft_mesh_grid_params p = sdft_mesh_grid_params_defaults();
    if (set_settings(SDFT_MESH_SETTINGS_GRID, &p, kw) < 0)
        return NULL;
    progress_call pc;
    progress_of(progress, &pc, &p.progress, &p.progress_user);
    sdft_mesh_grid *g = NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_to_grid(self->mesh, &p, &g, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    PyObject *grid = e == SDFT_OK ? MeshGrid_wrap(g) : NULL;
    if (e == SDFT_OK && !grid)
        return NULL;
    return progress_result(&pc, e, msg, grid);
}

static PyMethodDef mesh_methods[] = {
    {"signed_distance", (PyCFunction)(void (*)(void))mesh_signed_distance, METH_VARARGS | METH_KEYWORDS, NULL},
    {"winding_number", (PyCFunction)mesh_winding_number, METH_O, NULL},
    {"samples", (PyCFunction)(void (*)(void))mesh_samples, METH_VARARGS | METH_KEYWORDS, NULL},
    {"info", (PyCFunction)mesh_info, METH_NOARGS, NULL},
    {"to_grid", (PyCFunction)(void (*)(void))mesh_to_grid, METH_VARARGS | METH_KEYWORDS, NULL},
    {NULL, NULL, 0, NULL}};

static PyTypeObject MeshType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sdftrace._sdftrace.Mesh",
    .tp_basicsize = sizeof(MeshObject),
    .tp_dealloc = (destructor)Mesh_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A triangle mesh held by libsdftrace_mesh (see sdftrace.Mesh).",
    .tp_methods = mesh_methods,
};

/* ---- MeshGrid: a converted grid --------------------------------------- */

HANDLE_OBJECT(MeshGrid, sdft_mesh_grid, grid, sdft_mesh_grid_free)

static PyObject *mesh_grid_write(MeshGridObject *self, PyObject *args, PyObject *kw)
{
    static char *names[] = {"path", "fp16", NULL};
    PyObject *path_obj;
    int fp16 = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O&|p", names, PyUnicode_FSConverter, &path_obj, &fp16))
        return NULL;
    /* The format by the path's extension. */
    static const struct {
        const char *ext;
        sdft_mesh_format format;
    } formats[] = {{".vdb", SDFT_MESH_FORMAT_VDB}, {".nvdb", SDFT_MESH_FORMAT_NVDB}, {".npy", SDFT_MESH_FORMAT_NPY}};
    const char *path = PyBytes_AS_STRING(path_obj);
    const size_t len = strlen(path);
    int format = -1;
    for (size_t i = 0; i < sizeof formats / sizeof *formats; i++) {
        const size_t n = strlen(formats[i].ext);
        if (len >= n && strcmp(path + len - n, formats[i].ext) == 0)
            format = (int)formats[i].format;
    }
    char msg[MSG_LEN] = "";
    if (format < 0) {
        snprintf(msg, sizeof msg, "%s: unknown extension (use .vdb, .nvdb or .npy)", path);
        Py_DECREF(path_obj);
        return raise_error(SDFT_EINVAL, msg);
    }
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_grid_write(self->grid, path, (sdft_mesh_format)format, fp16, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    Py_DECREF(path_obj);
    if (e != SDFT_OK)
        return raise_error(e, msg);
    Py_RETURN_NONE;
}

static PyObject *mesh_grid_box(MeshGridObject *self, PyObject *unused)
{
    (void)unused;
    sdft_mesh_grid_box b;
    sdft_mesh_grid_stats s;
    char msg[MSG_LEN] = "";
    sdft_error e = sdft_mesh_grid_get_box(self->grid, &b, msg, sizeof msg);
    if (e == SDFT_OK)
        e = sdft_mesh_grid_get_stats(self->grid, &s, msg, sizeof msg);
    if (e != SDFT_OK)
        return raise_error(e, msg);
    return Py_BuildValue("{s(iii)s(ddd)sdsfsKsK}", "dims", b.dims[0], b.dims[1], b.dims[2], "origin", b.origin[0],
                         b.origin[1], b.origin[2], "voxel_size", b.voxel_size, "background", b.background,
                         "active_voxels", s.active_voxels, "ambiguous_voxels", s.ambiguous_voxels);
}

static PyObject *mesh_grid_dense(MeshGridObject *self, PyObject *unused)
{
    (void)unused;
    sdft_mesh_grid_box b;
    char msg[MSG_LEN] = "";
    sdft_error e = sdft_mesh_grid_get_box(self->grid, &b, msg, sizeof msg);
    if (e != SDFT_OK)
        return raise_error(e, msg);
    npy_intp dims[3] = {b.dims[0], b.dims[1], b.dims[2]};
    PyArrayObject *a = new_floats(3, dims);
    if (!a)
        return NULL;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_grid_dense(self->grid, (float *)PyArray_DATA(a), (size_t)PyArray_SIZE(a), msg, sizeof msg);
    PyEval_RestoreThread(ts);
    if (e != SDFT_OK) {
        Py_DECREF(a);
        return raise_error(e, msg);
    }
    return (PyObject *)a;
}

static PyObject *NanoGrid_wrap(sdft_grid *handle);

static PyObject *mesh_grid_nano(MeshGridObject *self, PyObject *unused)
{
    (void)unused;
    sdft_grid *g = NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_mesh_grid_nano(self->grid, &g, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    return e == SDFT_OK ? NanoGrid_wrap(g) : raise_error(e, msg);
}

static PyMethodDef mesh_grid_methods[] = {
    {"write", (PyCFunction)(void (*)(void))mesh_grid_write, METH_VARARGS | METH_KEYWORDS, NULL},
    {"box", (PyCFunction)mesh_grid_box, METH_NOARGS, NULL},
    {"dense", (PyCFunction)mesh_grid_dense, METH_NOARGS, NULL},
    {"nano", (PyCFunction)mesh_grid_nano, METH_NOARGS, NULL},
    {NULL, NULL, 0, NULL}};

static PyTypeObject MeshGridType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sdftrace._sdftrace.MeshGrid",
    .tp_basicsize = sizeof(MeshGridObject),
    .tp_dealloc = (destructor)MeshGrid_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A grid converted from a mesh (see sdftrace.Grid).",
    .tp_methods = mesh_grid_methods,
};

/* ---- NanoGrid: the tracer's grid --------------------------------------- */

HANDLE_OBJECT(NanoGrid, sdft_grid, grid, sdft_grid_free)

static PyObject *open_grid(PyObject *module, PyObject *args, PyObject *kw)
{
    (void)module;
    static char *names[] = {"path", "name", NULL};
    PyObject *path_obj;
    const char *name = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O&|z", names, PyUnicode_FSConverter, &path_obj, &name))
        return NULL;
    sdft_grid_options o = sdft_grid_options_defaults();
    o.path = PyBytes_AS_STRING(path_obj);
    o.name = name;
    sdft_grid *g = NULL;
    char msg[MSG_LEN] = "";
    sdft_error e;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_vdb_open(&o, &g, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    Py_DECREF(path_obj);
    return e == SDFT_OK ? NanoGrid_wrap(g) : raise_error(e, msg);
}

/* Trilinear values at points, through the field's sampler (sdft_grid_sample). */
static PyObject *nano_grid_sample(NanoGridObject *self, PyObject *points)
{
    sdft_mesh_points pts;
    PyArrayObject *in = points_of(points, &pts);
    if (!in)
        return NULL;
    npy_intp n = (npy_intp)pts.count;
    PyArrayObject *out = new_floats(1, &n);
    if (!out) {
        Py_DECREF(in);
        return NULL;
    }
    float *v = (float *)PyArray_DATA(out);
    const char *data = (const char *)pts.data;
    PyThreadState *ts = PyEval_SaveThread();

    {
        const sdft_field f = sdft_grid_field(self->grid, SDFT_GRID_BOUND_NONE);
        sdft_scratch s;
        memset(&s, 0, sizeof s);
        sdft_scratch_init(&f, &s);
        for (npy_intp i = 0; i < n; i++) {
            float p[3];
            for (int k = 0; k < 3; k++) {
                const char *at = data + i * pts.stride[0] + k * pts.stride[1];
                p[k] = pts.type == SDFT_MESH_FLOAT32 ? *(const float *)at : (float)*(const double *)at;
            }
            v[i] = sdft_grid_sample(self->grid, SDFT_GRID_BOUND_NONE, &s, sdft_v3(p[0], p[1], p[2]), NULL);
        }
    }
    PyEval_RestoreThread(ts);
    Py_DECREF(in);
    return (PyObject *)out;
}

/* The active voxels' index box densely, C order (x, y, z), and its lower corner. */
static PyObject *nano_grid_dense(NanoGridObject *self, PyObject *unused)
{
    (void)unused;
    int32_t lo[3], hi[3];
    sdft_grid_index_bounds(self->grid, lo, hi);
    npy_intp dims[3];
    for (int k = 0; k < 3; k++)
        dims[k] = hi[k] >= lo[k] ? (npy_intp)hi[k] - lo[k] + 1 : 0;
    PyArrayObject *a = new_floats(3, dims);
    if (!a)
        return NULL;
    float *v = (float *)PyArray_DATA(a);
    PyThreadState *ts = PyEval_SaveThread();
    for (npy_intp i = 0; i < dims[0]; i++)
        for (npy_intp j = 0; j < dims[1]; j++)
            for (npy_intp k = 0; k < dims[2]; k++)
                v[(i * dims[1] + j) * dims[2] + k] =
                    sdft_grid_voxel(self->grid, lo[0] + (int32_t)i, lo[1] + (int32_t)j, lo[2] + (int32_t)k, NULL);
    PyEval_RestoreThread(ts);
    return Py_BuildValue("(N(iii))", a, lo[0], lo[1], lo[2]);
}

static PyObject *nano_grid_info(NanoGridObject *self, PyObject *unused)
{
    (void)unused;
    const sdft_vec3 h = sdft_grid_voxel_size(self->grid);
    const sdft_aabb b = sdft_grid_world_bounds(self->grid);
    return Py_BuildValue("{sssssss(fff)sfsKs(fff)s(fff)}", "name", sdft_grid_name(self->grid), "type",
                         sdft_grid_type_name(self->grid), "class", sdft_grid_class_name(self->grid), "voxel_size", h.x,
                         h.y, h.z, "background", sdft_grid_background(self->grid), "active_voxels",
                         (unsigned long long)sdft_grid_active_voxels(self->grid), "lo", b.lo.x, b.lo.y, b.lo.z, "hi",
                         b.hi.x, b.hi.y, b.hi.z);
}

static PyMethodDef nano_grid_methods[] = {{"sample", (PyCFunction)nano_grid_sample, METH_O, NULL},
                                          {"dense", (PyCFunction)nano_grid_dense, METH_NOARGS, NULL},
                                          {"info", (PyCFunction)nano_grid_info, METH_NOARGS, NULL},
                                          {NULL, NULL, 0, NULL}};

static PyTypeObject NanoGridType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "sdftrace._sdftrace.NanoGrid",
    .tp_basicsize = sizeof(NanoGridObject),
    .tp_dealloc = (destructor)NanoGrid_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A NanoVDB grid the tracer renders (see sdftrace.Grid).",
    .tp_methods = nano_grid_methods,
};

/* ---- render --------------------------------------------------------- */

static int vec3_of(PyObject *o, sdft_vec3 *v)
{
    if (o == NULL || o == Py_None)
        return 1;
    return PyArg_ParseTuple(o, "fff", &v->x, &v->y, &v->z);
}

/* The image's planes as numpy arrays, which sdft_render fills in place:
 * a dict of them, with *img pointing into them, or NULL with an exception. */
static PyObject *image_planes(int width, int height, sdft_image *img)
{
    npy_intp one[2] = {height, width}, three[3] = {height, width, 3};
    PyObject *planes = PyDict_New();
    const struct {
        const char *name;
        int ndim, type;
        void **plane;
    } rows[] = {{"depth", 2, NPY_FLOAT32, (void **)&img->depth},
                {"normal", 3, NPY_FLOAT32, (void **)&img->normal},
                {"rgb", 3, NPY_FLOAT32, (void **)&img->rgb},
                {"steps", 2, NPY_UINT32, (void **)&img->steps},
                {"primary_steps", 2, NPY_UINT32, (void **)&img->primary_steps},
                {"fallbacks", 2, NPY_UINT32, (void **)&img->fallbacks},
                {"status", 2, NPY_UINT8, (void **)&img->status}};
    for (size_t i = 0; planes && i < sizeof rows / sizeof *rows; i++) {
        PyObject *a = PyArray_SimpleNew(rows[i].ndim, rows[i].ndim == 2 ? one : three, rows[i].type);
        if (!a || PyDict_SetItemString(planes, rows[i].name, a) < 0)
            Py_CLEAR(planes);
        else
            *rows[i].plane = PyArray_DATA((PyArrayObject *)a);
        Py_XDECREF(a);
    }
    img->width = width;
    img->height = height;
    return planes;
}

static PyObject *render(PyObject *module, PyObject *args, PyObject *kw)
{
    (void)module;
    static char *names[] = {"source", "width", "height", "eye",     "target",  "up",
                            "fov",    "light", "method", "shadows", "threads", NULL};
    PyObject *source, *eye = NULL, *target = NULL, *up = NULL, *light = NULL;
    sdft_render_params p = sdft_render_defaults();
    const char *method = "auto";
    float fov = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|iiOOOfOspi", names, &source, &p.width, &p.height, &eye, &target, &up,
                                     &fov, &light, &method, &p.shadows, &p.threads))
        return NULL;
    sdft_field field;
    char msg[MSG_LEN] = "";
    if (PyUnicode_Check(source)) {
        const sdft_scene *scene = sdft_scene_find(PyUnicode_AsUTF8(source));
        if (!scene)
            return raise_error(SDFT_EINVAL, "no such scene (see sdftrace.scenes())");
        field = scene->field;
        p.camera = scene->camera;
        p.light = scene->light;
    } else if (PyObject_TypeCheck(source, &NanoGridType)) {
        const sdft_grid *g = ((NanoGridObject *)source)->grid;
        field = sdft_grid_field(g, SDFT_GRID_BOUND_FAR);
        p.camera = sdft_camera_front(sdft_grid_world_bounds(g), p.width, p.height, 40.0f);
        const sdft_vec3 c = p.camera.at;
        const float dist = p.camera.from.z - c.z;
        p.light = sdft_v3(c.x, c.y + 2.0f * dist, c.z + dist);
    } else {
        PyErr_SetString(PyExc_TypeError, "render takes a scene name or a grid");
        return NULL;
    }
    if (!vec3_of(eye, &p.camera.from) || !vec3_of(target, &p.camera.at) || !vec3_of(up, &p.camera.up) ||
        !vec3_of(light, &p.light))
        return NULL;
    if (fov > 0)
        p.camera.fov_deg = fov;
    sdft_error e = sdft_method_parse(method, &p.trace.method, msg, sizeof msg);
    if (e != SDFT_OK)
        return raise_error(e, msg);
    p.trace.omega = sdft_default_omega(p.trace.method);
    if (p.width < 1 || p.height < 1 || p.width > 16384 || p.height > 16384)
        return raise_error(SDFT_EINVAL, "width and height must be 1..16384");
    sdft_image img;
    memset(&img, 0, sizeof img);
    PyObject *planes = image_planes(p.width, p.height, &img);
    if (!planes)
        return NULL;
    PyThreadState *ts = PyEval_SaveThread();
    e = sdft_render(&field, &p, &img, NULL, msg, sizeof msg);
    PyEval_RestoreThread(ts);
    if (e != SDFT_OK) {
        Py_DECREF(planes);
        return raise_error(e, msg);
    }
    return planes;
}

static PyObject *scenes(PyObject *module, PyObject *unused)
{
    (void)module;
    (void)unused;
    size_t n = 0;
    const sdft_scene *const *all = sdft_scenes(&n);
    PyObject *list = PyList_New((Py_ssize_t)n);
    for (size_t i = 0; list && i < n; i++)
        PyList_SET_ITEM(list, (Py_ssize_t)i, PyUnicode_FromString(all[i]->name));
    return list;
}

/* ---- the module ------------------------------------------------------ */

static PyMethodDef module_methods[] = {
    {"load_mesh", (PyCFunction)(void (*)(void))load_mesh, METH_VARARGS | METH_KEYWORDS, NULL},
    {"mesh_from_arrays", (PyCFunction)(void (*)(void))mesh_from_arrays, METH_VARARGS | METH_KEYWORDS, NULL},
    {"open_grid", (PyCFunction)(void (*)(void))open_grid, METH_VARARGS | METH_KEYWORDS, NULL},
    {"render", (PyCFunction)(void (*)(void))render, METH_VARARGS | METH_KEYWORDS, NULL},
    {"scenes", (PyCFunction)scenes, METH_NOARGS, NULL},
    {"settings", (PyCFunction)settings, METH_O, NULL},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT,
    .m_name = "_sdftrace",
    .m_doc = "The C extension of the sdftrace package (import sdftrace).",
    .m_size = -1,
    .m_methods = module_methods,
};

PyMODINIT_FUNC PyInit__sdftrace(void)
{
    import_array();
    if (PyType_Ready(&MeshType) < 0 || PyType_Ready(&MeshGridType) < 0 || PyType_Ready(&NanoGridType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&module_def);
    if (!m)
        return NULL;
    Canceled =
        PyErr_NewExceptionWithDoc("sdftrace.Canceled", "A progress callable asked to stop.", PyExc_RuntimeError, NULL);
    if (!Canceled || PyModule_AddObject(m, "Canceled", Canceled) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    Py_INCREF(Canceled); /* the module's reference, and ours */
    Py_INCREF(&MeshType);
    Py_INCREF(&MeshGridType);
    Py_INCREF(&NanoGridType);
    if (PyModule_AddObject(m, "Mesh", (PyObject *)&MeshType) < 0 ||
        PyModule_AddObject(m, "MeshGrid", (PyObject *)&MeshGridType) < 0 ||
        PyModule_AddObject(m, "NanoGrid", (PyObject *)&NanoGridType) < 0 ||
        PyModule_AddIntConstant(m, "version", sdft_version()) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
