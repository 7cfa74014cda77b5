"""Design search: which damper, against a tuned mass damper of the same mass (pidamper design)."""
