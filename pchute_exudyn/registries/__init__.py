"""The registries: one record per kind of thing the rest of the package names (an output column, a confluence
method and an integrator, a canopy type), each table in one module, low in the layers so that every other layer
can read it. A new kind is one record here; nothing else compares names."""
