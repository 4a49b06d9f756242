/* Structural self-test fixture: mutual recursion across two translation units (with b). */
unsigned int fixture_even(unsigned int n);
unsigned int fixture_odd(unsigned int n);

unsigned int fixture_even(unsigned int n) { return (n == 0u) ? 1u : fixture_odd(n - 1u); }
