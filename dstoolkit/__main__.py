"""``python -m dstoolkit``: see :mod:`dstoolkit.cli`."""

from dstoolkit.cli import main

raise SystemExit(main())
