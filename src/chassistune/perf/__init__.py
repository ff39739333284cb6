"""Speed and accuracy figures of DESIGN 8, one module per area, each with `figures(quick)`."""
