// Proxy validation and inverse mappings: implemented in issue #2.
