"""Analyses that take a :class:`~reducerlab.model.Model` and return results."""
