"""The read planner's decisions that mutation testing found no test pinning.

Each test names the rule it checks; the planner's module docstring defines them.
"""
