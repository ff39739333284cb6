"""`python -m chassistune.cli`: the same as the `chassistune` console script. Guarded: spawned
worker processes re-import this module and must not start the command again."""

from chassistune.cli.main import main

if __name__ == "__main__":
    main()
