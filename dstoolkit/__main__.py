"""``python -m dstoolkit``: see :mod:`dstoolkit.cli`."""

from .cli import main

raise SystemExit(main())
