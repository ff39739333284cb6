"""Speed and accuracy figures of design.md 8, one module per area, each with `figures(quick)`."""
