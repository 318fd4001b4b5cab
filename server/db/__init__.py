"""Persistence: SQLAlchemy tables, the :class:`Database` handle and one repository module
per table (``machines``, ``error_models``, ``measurements``, ``maps``, ``reports``,
``events``). Repository functions take a session first and contain all the SQL; callers
in async code use ``await db.run(machines.get_machine, name)``."""

from server.db.database import Database, DatabaseUnavailable, make_engine
from server.db.errors import DuplicateError

__all__ = ["Database", "DatabaseUnavailable", "DuplicateError", "make_engine"]
