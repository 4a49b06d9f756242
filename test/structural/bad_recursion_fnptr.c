/* Structural self-test fixture: recursion hidden behind a function pointer. */
typedef unsigned int (*fixture_fn_t)(unsigned int n);

unsigned int fixture_apply(fixture_fn_t f, unsigned int n);

static unsigned int countdown(unsigned int n)
{
    return (n == 0u) ? 0u : fixture_apply(countdown, n - 1u);
}

unsigned int fixture_apply(fixture_fn_t f, unsigned int n) { return (n > 100u) ? 0u : f(n); }

unsigned int fixture_start(unsigned int n);
unsigned int fixture_start(unsigned int n) { return countdown(n); }
