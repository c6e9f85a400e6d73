"""Thin pythonfmu adapters over axir.models."""
