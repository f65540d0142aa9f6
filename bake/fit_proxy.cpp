// Proxy fitting with CGAL (SPEC section 6): implemented in issue #5.
