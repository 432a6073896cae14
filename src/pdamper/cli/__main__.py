"""``python -m pdamper.cli``: the pdamper command line."""

from . import main

if __name__ == "__main__":
    main()
