"""Matplotlib figures from results (imported only when a figure is drawn)."""
