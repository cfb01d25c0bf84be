"""Analyses: each takes a Design (or the generic :class:`~reducerlab.model.Model` it
builds) and returns a Result that knows how to show itself."""
