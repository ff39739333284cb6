"""`python -m chassistune.cli`: the same as the `chassistune` console script."""

from chassistune.cli.main import main

main()
