"""Import every command module so that it registers on the `cli` group."""

from chassistune.cli import list_cmd  # noqa: F401
