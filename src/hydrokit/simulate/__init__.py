"""Integrators and simulation drivers; they live outside the models."""
