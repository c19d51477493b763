"""What people use directly: the ``parakin`` command line (``cli``), the papers' examples (``demo``),
the printed tables of a mechanism (``display``), the readable symbolic model (``inspect``), the
drawings (``plot``) and the interactive browser viewer (``viewer``, with ``viewer.html``)."""
