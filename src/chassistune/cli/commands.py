"""Import every command module so that it registers on the `cli` group."""

from chassistune.cli import list_cmd  # noqa: F401
from chassistune.cli import fuzzy  # noqa: F401
