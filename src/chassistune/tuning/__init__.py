"""Tuning: connect any optimizer to the batch cost of a plant (design.md 5, 7)."""
