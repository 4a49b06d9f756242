/* Structural self-test fixture: dynamic memory (must be rejected by the nm check). */
#include <stdlib.h>

double *fixture_make(size_t n);
void fixture_drop(double *p);

double *fixture_make(size_t n) { return (double *)malloc(n * sizeof(double)); }
void fixture_drop(double *p) { free(p); }
