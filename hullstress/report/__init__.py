"""Writing a run's report folder: tables, summary, metadata."""

from .tables import failure_counts, status_counts
from .writer import RowStream, new_run_dir, write_report

__all__ = ["failure_counts", "status_counts", "RowStream", "new_run_dir", "write_report"]
