"""Design studies over many inputs or designs: dask sweeps of quantities over grids (``sweep``),
their maps (``atlas``), and sampled configurations near and away from singularities
(``sampling``)."""
