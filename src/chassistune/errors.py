"""The one exception type for bad input: the CLI turns it into one line on stderr and exit 2."""


class InputError(ValueError):
    """Bad user input. The message names the field and the problem, on one line."""

    def __init__(self, field: str, problem: str) -> None:
        self.field = field
        self.problem = problem
        super().__init__(f"{field}: {problem}")
