"""The prestressed Hertzian solid (kind ``hertz``). See README.md beside this file."""
