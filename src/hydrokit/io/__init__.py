"""File formats: rig, launch, vehicle, mission, force files; results as JSON/CSV."""
