"""Evaluation protocol helpers: statistics over repetitions and seeds, and result tables."""

from jaxmotion.evaluation.stats import Summary, summarize, t_critical_95
from jaxmotion.evaluation.table import format_table

__all__ = ["Summary", "summarize", "t_critical_95", "format_table"]
