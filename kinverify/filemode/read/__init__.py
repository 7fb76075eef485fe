"""Reading each file once: safe loading, xacro, cleaning for the libraries, written precision,
inertial validation, and each library's neutral description of the model."""
