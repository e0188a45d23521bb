"""``python -m seqtopo ...`` is the ``seqtopo`` command."""

from ._cli import main

main()
