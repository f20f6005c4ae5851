"""Pipelines: trained models put to use (generation, denoising, interpolation, pictures)."""
