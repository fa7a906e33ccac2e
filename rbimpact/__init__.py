"""rbimpact: algebraic collision laws with friction and an exact event-driven stepper."""
