/* py_mixed.c -- bindings (placeholder table). */
#include "pyext.h"

PyMethodDef phm_py_mixed_methods[] = {{NULL, NULL, 0, NULL}};
