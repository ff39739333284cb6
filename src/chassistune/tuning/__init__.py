"""Tuning: connect any optimizer to the batch cost of a plant (DESIGN 5, 7)."""
