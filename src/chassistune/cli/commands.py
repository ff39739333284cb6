"""Import every command module so that it registers on the `cli` group."""

from chassistune.cli import list_cmd  # noqa: F401
from chassistune.cli import fuzzy  # noqa: F401
from chassistune.cli import simulate  # noqa: F401
from chassistune.cli import demo  # noqa: F401
from chassistune.cli import bench  # noqa: F401
from chassistune.cli import optimize  # noqa: F401
from chassistune.cli import tune  # noqa: F401
from chassistune.cli import study  # noqa: F401
from chassistune.cli import export  # noqa: F401
