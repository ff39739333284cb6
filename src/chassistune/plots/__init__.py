"""Figures (matplotlib, imported lazily: computation never imports plotting)."""
