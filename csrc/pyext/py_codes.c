/* py_codes.c -- phmech._core.codes(): the core's code tables (csrc/util/codes.c), its pair
 * types (csrc/model/pair_types.c) and integrators (csrc/integrate/integrators.c) for Python, so that no code is retyped by hand across the boundary. */
#include "pyext.h"

/* {name: value} of a code table, or the list of its names (ordered by value = position) when
 * `as_list`; a new reference or NULL with an exception set. */
static PyObject *table_object(const phm_code_table *t, int as_list) {
  PyObject *o = as_list ? PyList_New(t->nrows) : PyDict_New();
  for (int i = 0; o && i < t->nrows; i++) {
    if (as_list) {
      PyObject *s = PyUnicode_FromString(t->rows[i].name);
      if (!s) Py_CLEAR(o);
      else PyList_SET_ITEM(o, t->rows[i].value, s);
    } else {
      PyObject *v = PyLong_FromLong(t->rows[i].value);
      if (!v || PyDict_SetItemString(o, t->rows[i].name, v) < 0) Py_CLEAR(o);
      Py_XDECREF(v);
    }
  }
  return o;
}

static PyObject *py_codes(PyObject *self, PyObject *noargs) {
  (void)self;
  (void)noargs;
  PyObject *d = PyDict_New(), *pairs = PyDict_New();
  if (!pairs) Py_CLEAR(d);
  for (int i = 0; d && pairs && i < phm_pair_type_count(); i++) {
    PyObject *v = PyLong_FromLong(i);
    if (!v || PyDict_SetItemString(pairs, phm_pair_type(i)->name, v) < 0) Py_CLEAR(d);
    Py_XDECREF(v);
  }
  if (d && PyDict_SetItemString(d, "pair_types", pairs) < 0) Py_CLEAR(d);
  Py_XDECREF(pairs);
  PyObject *integ = d ? PyDict_New() : NULL; /* the table of integrators (csrc/integrate/integrators.c) */
  if (!integ) Py_CLEAR(d);
  for (int i = 0; d && i < phm_integrator_count(); i++) {
    PyObject *v = PyLong_FromLong(i);
    if (!v || PyDict_SetItemString(integ, phm_integrator_name(i), v) < 0) Py_CLEAR(d);
    Py_XDECREF(v);
  }
  if (d && PyDict_SetItemString(d, "integrators", integ) < 0) Py_CLEAR(d);
  Py_XDECREF(integ);
  for (int k = 0; d && k < phm_code_table_count(); k++) {
    const phm_code_table *t = phm_code_table_at(k);
    PyObject *o = table_object(t, t->rows == phm_code_table_named("result_fields")->rows);
    if (!o || PyDict_SetItemString(d, t->name, o) < 0) Py_CLEAR(d);
    Py_XDECREF(o);
  }
  return d;
}

/* Row f of the table of result quantities as a dict (result_fields). */
static PyObject *result_field_dict(int f, const void *ctx) {
  (void)ctx;
  const phm_result_field *r = phm_result_field_at(f);
  long shape[3];
  const char *names[3] = {NULL, NULL, NULL};
  int nd = phm_result_shape(NULL, -1, f, shape, names);
  PyObject *dims = phm_py_str_tuple(names, nd);
  PyObject *d = dims ? Py_BuildValue("{s:s,s:O,s:s,s:s,s:s}", "name", r->name, "dims", dims, "unit",
                                     r->unit, "noun", r->noun, "text", r->text)
                     : NULL;
  Py_XDECREF(dims);
  return d;
}

/* result_fields() -> [{name, dims, unit, noun, text}, ...]: the table of result quantities
 * (csrc/include/phmech_results.h) in its order, dims the names of one output's dimensions. */
static PyObject *py_result_fields(PyObject *self, PyObject *noargs) {
  (void)self;
  (void)noargs;
  return phm_py_list(PHM_NRESULT_FIELDS, result_field_dict, NULL);
}

PyMethodDef phm_py_codes_methods[] = {
    {"codes", py_codes, METH_NOARGS,
     "codes() -> dict: the core's code tables, from its C enums: pair_types, law_kinds, "
     "integrators, actuator_kinds, mass_kinds ({name: code}, names lower case) and result_fields "
     "(list: the names of the arrays simulate returns, in the core's order)."},
    {"result_fields", py_result_fields, METH_NOARGS,
     "result_fields() -> [dict(name, dims, unit, noun, text)]: the table of result quantities "
     "(csrc/include/phmech_results.h) in the core's order; dims names one output's dimensions "
     "(e.g. ('pair', 'component'))."},
    {NULL, NULL, 0, NULL}};
