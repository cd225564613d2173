/* py_model.c -- bindings (placeholder table). */
#include "pyext.h"

PyMethodDef phm_py_model_methods[] = {{NULL, NULL, 0, NULL}};
