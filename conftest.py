"""Makes the checkout's own ``domes`` importable first in tests (pytest puts this directory on sys.path)."""
