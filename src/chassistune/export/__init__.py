"""Export a tuned controller where engineers deploy it: C99, an FMI 2.0 source FMU, MATLAB, JSON."""
