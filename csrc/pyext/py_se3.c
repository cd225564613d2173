/* py_se3.c -- bindings (placeholder table). */
#include "pyext.h"

PyMethodDef phm_py_se3_methods[] = {{NULL, NULL, 0, NULL}};
