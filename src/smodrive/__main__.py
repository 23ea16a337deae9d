"""``python -m smodrive``: the command line (:mod:`smodrive.cli`), as the
``smodrive`` command."""

from .cli import main

if __name__ == "__main__":
    main(prog_name="smodrive")
