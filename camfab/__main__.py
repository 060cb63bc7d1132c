"""``python -m camfab`` runs the command line."""

from camfab.start import main

main()
