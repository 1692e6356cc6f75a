"""Generic numerics: integrators, root finding, quadrature, special functions, linear algebra.

Nothing here knows about an exercise; each tool has a direct conformance test against scipy or closed forms."""
