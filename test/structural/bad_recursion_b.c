/* Structural self-test fixture: mutual recursion across two translation units (with a). */
unsigned int fixture_even(unsigned int n);
unsigned int fixture_odd(unsigned int n);

unsigned int fixture_odd(unsigned int n) { return (n == 0u) ? 0u : fixture_even(n - 1u); }
