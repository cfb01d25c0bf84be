"""``python -m reducerlab`` runs the command line."""

from .cli import main

main()
