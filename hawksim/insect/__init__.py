"""The insect: morphology (Table 1 and literature), wing kinematics (Eq. 1, Tables 2-3), the generated MJCF
model, and the named accessors into it."""
