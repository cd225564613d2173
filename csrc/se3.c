/* se3.c -- placeholder until its owner fills it in. */
#include "phmech.h"
