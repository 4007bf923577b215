C     SQRT as the IBM 1410 FORTRAN library did it (C28-0328-3, p. 23):
C     a negative argument prints an error message and the result is the
C     square root of its absolute value.  gfortran's intrinsic returns
C     NaN instead, and then ARCCOS's series never meets its 1E-8 test.
C     tests/fortran.py links this routine when asked for the 1410
C     library, declaring SQRT EXTERNAL in each program unit of the deck
C     (the deck itself is left as the listing).
      FUNCTION SQRT(X)
      IF (X .LT. 0.0) WRITE(0,10) X
   10 FORMAT(' SQRT OF NEGATIVE ARGUMENT',E24.16)
      SQRT=DSQRT(ABS(X))
      RETURN
      END
