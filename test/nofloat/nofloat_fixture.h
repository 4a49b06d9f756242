/* Shared by the no-float checker's fixtures: the freestanding headers a fixed-point module may
 * use. */
#ifndef NOFLOAT_FIXTURE_H
#define NOFLOAT_FIXTURE_H

#include <stddef.h>
#include <stdint.h>

#endif
