"""The report stage: a run's records become its files (tables, summary, failure folders, HTML, JUnit); it runs nothing."""

from .tables import failure_counts, status_counts
from .writer import RowStream, new_run_dir, write_report

__all__ = ["failure_counts", "status_counts", "RowStream", "new_run_dir", "write_report"]
