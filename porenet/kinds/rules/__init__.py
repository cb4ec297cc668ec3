"""The rule-based pattern classifier (kind ``rules``). See README.md beside this file."""
