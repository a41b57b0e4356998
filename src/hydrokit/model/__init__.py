"""Vehicle model (Fossen form + general derivative terms), thrusters, allocation, control."""
