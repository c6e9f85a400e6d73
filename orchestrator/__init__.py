"""fmpy-based master algorithm, system description, recording, campaigns and CLI."""
