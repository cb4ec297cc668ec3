"""The frictional solid (kind ``hertz-mindlin``). See README.md beside this file."""
