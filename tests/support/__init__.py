"""What several test modules share: fixtures, builders and constants.

Test modules import from here and never from each other, so each ``test_*.py`` holds only
tests and can be read, moved or deleted alone (``tests/test_layout.py`` checks this).
"""
