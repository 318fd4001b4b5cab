"""What the model gets wrong: candidate effects judged on held-out readings, and the report.
"""
