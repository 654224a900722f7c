"""MPMICE postprocessing: read dumps, analytic solutions, comparisons and plots."""
