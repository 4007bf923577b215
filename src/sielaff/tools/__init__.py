"""One module per user command (``run`` and ``diff``, ``check``, ``plot``, ``punch``,
``table``, ``bench``, ``help``) and what they share: ``common`` (loading a deck with its
checks, the one-line errors and exit statuses, signals), ``output`` (files written whole
or not at all), ``progress``.  Commands never import each other.
"""
