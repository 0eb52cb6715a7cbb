"""``python -m domes`` runs the command-line interface."""

from domes.cli import main

raise SystemExit(main())
