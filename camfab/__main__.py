"""``python -m camfab`` runs the command line."""

from camfab.cli import main

main()
