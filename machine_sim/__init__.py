"""Simulated Fanuc-style and Siemens-style machine tools with a physics the center does not know."""
