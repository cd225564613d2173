import phmech; print("demo placeholder")
