// The thesis' robot sketch, "ANEXO A, Codigo del robot", transcribed from the
// printed listing: its statements, constants, function names and order as
// printed, quirks included (see ../../README.md, "Quirks of the thesis build").
// Where the OCR'd text is garbled, the reading chosen is an `// OCR:` comment
// at the spot (README.md beside this file lists them). Nothing here is added
// for a test bench.

//CONTROL PID DE LA LLANTA DERECHA E IZQUIERDA

#define RH_ENCODER_A 3
#define RH_ENCODER_B 5
#define LH_ENCODER_A 2
#define LH_ENCODER_B 4

#define VERDE 10
#define AZUL 11
#define ROJO 12

// variables to store the number of encoder pulses
// for each motor

// OCR: the initialisers are lost ("Il o oo"); read as "= 0".
volatile long leftCount = 0;
volatile long rightCount = 0;

//Variables de odometria

float Constante = 0.1669339526; //constante hallada mediante ecuaciones de Odometria

// OCR: "float DU R / float DU L / float DU i =" with their "= 0" scattered; read as below.
float DU_R = 0;
float DU_L = 0;
float DU_i = 0;
// OCR: printed "float DU_ = 0;" (unused); kept as the name printed.
float DU_ = 0;
float D_TETA = 0;

float Distancia=400; //Distancia en milimetros

int b = 130; //Distancia entre llantas en milimetros
int Flag_Giro_D = 0;
int Flag_Giro_I = 0;
int Flag_Contador = 0;
// OCR: printed without an initialiser ("Selector Exp;"); a global, so 0.
int Selector_Exp;
// OCR: printed "flag Arranque" with a lower-case f (unused); kept.
int flag_Arranque = 0;

//Variables de tiempo

// OCR: the four lines are interleaved ("double Tiempo s = / int / double
// Tiempo_ Actual / Flag_One = 1;"); read as these declarations, in this order.
double Tiempo_s = 0;
double Tiempo_Actual = 0;
int Flag_One = 1;
double Muestreo = 0.015;//tiempo de muestro del controlador PID

//Variables de velocidad llanta derecha

double Conteo_Actual_D = 0;
double Conteo_D = 0;
double Pulsos_Min_D = 0;
float RPM_Enc_D = 0;
float RPM_Mot_D = 0;
float Frecuencia_D = 0;

//Variables de velocidad llanta izquierda

double Conteo_Actual_I = 0;
double Conteo_I = 0;
double Pulsos_Min_I = 0;
float RPM_Enc_I = 0; // OCR: "= O;" (letter O) read as 0.
float RPM_Mot_I = 0; // OCR: "RPM Mot I 0" (the "=" lost).
float Frecuencia_I = 0;

//Variables de control llanta derecha

double Error_D = 0; //Diferencia entre Sepoint (Set D) y valor actual de velocidad
double Set_D = 14.47; //Setpoint llanta derecha
double U_D = 0;
double P_D = 0;
double I_D = 0;
double D_D = 0;
double pwm_D = 50;
double Kp_D = 2.74; //Proporcional llanta derecha
double Ki_D = 45.66; //Constante integral llanta derecha
double Kd_D = 0.0411; //Constante derivativa llanta derecha
double Error_Pasado_D = 0;
double Error_Anterior_D = 0;
double ErrorD_D = 0;

//Variables de control llanta izquierda

double Error_I = 0;//Diferencia entre Sepoint (Set I) y valor actual de velocidad
double Set_I = 15; // OCR: "Set T 15" read as "Set_I = 15".
// OCR: the initialisers of U_I .. D_I are lost ("I oo ool"); read as "= 0".
double U_I = 0;
double P_I = 0;
double I_I = 0;
double D_I = 0;
double pwm_I = 50; // OCR: "pwm T" read as pwm_I; its "50;" printed apart.
double Kp_I = 2.20;//Proporcional llanta izquierda
double Ki_I = 36.666;//Constante integral llanta izquierda
double Kd_I = 0.033;//Constante derivativa llanta izquierda
double Error_Pasado_I = 0;
double Error_Anterior_I = 0;
double ErrorD_I = 0;

//Variables de nivel de bateria

float Nivel = 0;

void setup() {

  // OCR: "BO0000001l" read as B00000001.
  TCCR2B = TCCR2B & B11111000 | B00000001; //PWM a 31372.55 Hz Puertos 9 y 10
  TCCR4B = TCCR4B & B11111000 | B00000001; //PWM a 31372.55 Hz Puertos 6,7 y 8

  Serial.begin(9600); //Puerto serial para monitoreo USB
  Serial1.begin(9600); //Puerto serial para comunicacion Bluetooth // OCR: "Seriall" read as Serial1.

  //Declaracion como entradas los puertos para el encoder izquierdo
  pinMode(LH_ENCODER_A, INPUT);
  pinMode(LH_ENCODER_B, INPUT);

  //Declaracion como entradas los puertos para el encoder derecho
  pinMode(RH_ENCODER_A, INPUT);
  pinMode(RH_ENCODER_B, INPUT); // OCR: "RHiENCODERiB" read as RH_ENCODER_B.

  //Declaracion de puertos como salida para medicion de nivel de bateria
  pinMode(VERDE, OUTPUT);
  pinMode(AZUL, OUTPUT);
  pinMode(ROJO, OUTPUT);

  //Entrada analoga A0 para medicion del divisor de voltaje para el nivel de bateria

  // OCR: a "}" is printed before this line (a page break); setup() is read
  // as ending after the println below.
  pinMode(A0, INPUT);

  attachInterrupt(0, leftEncoderEvent, CHANGE); //Interrupcion encoder izquierdo
  attachInterrupt(1, rightEncoderEvent, CHANGE); //Interrupcion endoder derecho

  Serial.println("Realizacion de test...");
}

void loop() {

  Nivel_Bateria();

  if (Serial1.available()) {

    Selector_Exp = Serial1.read();
    Serial.println(Selector_Exp);

    switch (Selector_Exp) {

      case 2:
        UMBmark_CW();
        break;

      case 3:
        UMBmark_CCW();
        break;

      case 4:
        Linear_Path_Test();
        break;

      case 5:
        Triangular_Path_Test();
        break;
    }
  }
  // OCR: the closing braces of the switch, the if and loop() are lost;
  // read as closing here.
}

void UMBmark_CW() {

  while ((Selector_Exp == 2) && (Flag_Contador <= 3))
  { // OCR: this "{" is lost.
    Adelante();
    Desplazamiento();
    Nivel_Bateria();

    if (DU_i >= Distancia) //Si distancia recorrida es igual a 4 metros
    {

      Flag_Contador++;

      Inercia_Stop_Ad();

      Stop_General();

      rightCount = 0;

      leftCount = 0;

      DU_i = 0;
      DU_L = 0;
      DU_R = 0;

      Flag_Giro_I = 1;

      Flag_Giro_D = 1;

      // OCR: the closing braces after this block are lost; the turn is read
      // as inside "if (DU_i >= Distancia)" (a turn after every leg, and this
      // test then always true), as the Rust port reads it.
      if (Flag_Contador <= 4 ) {
        Giro_CW();
      }
    }
  }
}

void Giro_CW() {
  while ((Flag_Giro_D == 1) || (Flag_Giro_I == 1)) {

    analogWrite(7, pwm_D); // LLANTA DERECHA ADELANTE
    analogWrite(8, pwm_I); // LLANTA IZQUIERDA ATRAS
    PID();

    if ((abs(leftCount)) >= 612) {
      analogWrite(7, 0);
      leftCount = 0;
      Flag_Giro_I = 0;

    }

    if ((abs(rightCount)) >= 612) {
      analogWrite(8, 0);
      rightCount = 0;
      Flag_Giro_D = 0;
    }
  }

  Inercia_Stop_Izq(); // OCR: "Inercia Stop Izg" read as Inercia_Stop_Izq.
  Stop_General();

  //***Reinicio de todas las variables***
  // As printed: pwm_D twice, pwm_I is not reset.
  pwm_D = 0;

  pwm_D = 0;

  // OCR: printed "UI-=20;" then "UD=0;"; read as U_I = 0; U_D = 0; (the
  // Rust port's reading; U is recomputed before any use either way).
  U_I = 0;
  U_D = 0;

  // OCR: the "= 0;" of these three lines are printed apart ("0; - 0;").
  Error_Pasado_D = 0;
  Error_Anterior_D = 0;
  ErrorD_D = 0;

  Error_Pasado_I = 0;
  Error_Anterior_I = 0;
  ErrorD_I = 0;

  //Variables de velocidad llanta derecha

  Conteo_Actual_D = 0;

  Conteo_D = 0;

  Pulsos_Min_D = 0; // OCR: "0O;" read as 0.
  RPM_Enc_D = 0;
  RPM_Mot_D = 0;
  Frecuencia_D = 0;

  //Variables de velocidad llanta izquierda

  Conteo_Actual_I = 0; // OCR: "Conteo Actual T" with its "0;" printed apart.
  Conteo_I = 0;

  Pulsos_Min_I = 0; // OCR: "0O;" read as 0.
  RPM_Enc_I = 0;
  RPM_Mot_I = 0;
  Frecuencia_I = 0;

}

void UMBmark_CCW()
{

  // OCR: the condition is scattered ("((Selector Exp ... ) && (Flag Contador
  // <= 3))"); read as UMBmark_CW's with the selector 3.
  while ((Selector_Exp == 3) && (Flag_Contador <= 3))

  {

    Adelante();
    Desplazamiento();

    Nivel_Bateria();

    if (DU_i >= Distancia)
    {

      Flag_Contador++;
      Inercia_Stop_Ad();
      Stop_General();
      rightCount = 0;
      leftCount = 0;
      DU_i = 0;
      DU_L = 0;
      DU_R = 0; // OCR: "DU R 0;" (the "=" lost).
      Flag_Giro_I = 1;
      Flag_Giro_D = 1;
      // OCR: the condition "(Flag Contador <= 4 ) {" is printed among the
      // lines of Giro_CCW(); read as here, inside "if (DU_i >= Distancia)"
      // like UMBmark_CW's.
      if (Flag_Contador <= 4 ) {

        Giro_CCW();
      }
    }

  }
}

void Giro_CCW() { // OCR: "({" read as "{".
  // OCR: printed "while ((Flag_Giro_D == ... )) A | (Flag_Giro_I == ...";
  // read as Giro_CW's condition.
  while ((Flag_Giro_D == 1) || (Flag_Giro_I == 1)) {

    analogWrite(6, pwm_D); // LLANTA DERECHA ADELANTE
    analogWrite(9, pwm_I); // LLANTA IZQUIERDA ATRAS
    PID();

    if ((abs(leftCount)) >= 612) {
      analogWrite(6, 0);
      leftCount = 0;
      Flag_Giro_I = 0;

    }

    if ((abs(rightCount)) >= 612) {
      analogWrite(9, 0);
      rightCount = 0;
      Flag_Giro_D = 0;
    }
  }

  Inercia_Stop_Der();
  Stop_General();

  //***Reinicio de todas las variables***

  pwm_D = 0;

  pwm_D = 0;

  // OCR: printed "UI-=0;" then "UD=0;"; read as U_I = 0; U_D = 0;
  U_I = 0;

  U_D = 0;

  Error_Pasado_D = 0;
  Error_Anterior_D = 0;
  ErrorD_D = 0;

  Error_Pasado_I = 0;
  Error_Anterior_I = 0;

  ErrorD_I = 0;
  //Variables de velocidad llanta derecha
  Conteo_Actual_D = 0;

  Conteo_D = 0;
  Pulsos_Min_D = 0;

  RPM_Enc_D = 0;
  RPM_Mot_D = 0;
  Frecuencia_D = 0;

  //Variables de velocidad llanta izquierda

  Conteo_Actual_I = 0;
  Conteo_I = 0;
  Pulsos_Min_I = 0; // OCR: "O;" read as 0.

  RPM_Enc_I = 0;
  RPM_Mot_I = 0;
  Frecuencia_I = 0;
}
void Linear_Path_Test() {
  Stop_General();
  while ((Selector_Exp == 4)&&(Flag_Contador == 0))
  {
    Adelante();
    Desplazamiento();
    if (DU_i >= Distancia)
    {
      Inercia_Stop_Ad();
      Stop_General();
      rightCount = 0;
      leftCount = 0;

      DU_i = 0;
      DU_L = 0;
      DU_R = 0;

      Flag_Contador=1; // OCR: "1l;" read as 1.

      // OCR: the closing braces of the if and the while are lost.
    }
  }
}
void Triangular_Path_Test() {

  while ((Selector_Exp == 5) && (Flag_Contador <= 2))
  {

    Adelante();
    Desplazamiento();

    if (DU_i >= Distancia)
    {
      Flag_Contador++;
      Inercia_Stop_Ad();
      Stop_General();
      rightCount = 0;
      leftCount = 0;

      DU_i = 0; // OCR: "DU 1" read as DU_i.
      DU_L = 0;
      DU_R = 0;

      Flag_Giro_I = 1;

      Flag_Giro_D = 1;

      // OCR: one closing brace is lost; the turn is read as inside
      // "if (DU_i >= Distancia)", as in the UMBmark tests.
      if (Flag_Contador <= 3 ) {
        Giro_CCW_Triang();

      }
    }
  }
}
void Giro_CCW_Triang() {
  while ((Flag_Giro_D == 1) || (Flag_Giro_I == 1)) {
    analogWrite(6, pwm_D); // LLANTA DERECHA ADELANTE
    analogWrite(9, pwm_I); // LLANTA IZQUIERDA ATRAS
    PID();
    if ((abs(leftCount)) >= 815.5) {
      analogWrite(6, 0);
      leftCount = 0;
      Flag_Giro_I = 0;
    }
    if ((abs(rightCount)) >= 815.5) {

      analogWrite(9, 0);
      rightCount = 0;

      Flag_Giro_D = 0;
    }
  }

  Inercia_Stop_Der();
  Stop_General();

  //***Reinicio de todas las variables***

  pwm_D = 0;

  pwm_D = 0;

  // OCR: printed "UI-=0;" then "UD=0;"; read as U_I = 0; U_D = 0;
  U_I = 0;

  U_D = 0;

  Error_Pasado_D = 0;
  Error_Anterior_D = 0;
  ErrorD_D = 0; // OCR: "0O;" read as 0.

  Error_Pasado_I = 0;
  Error_Anterior_I = 0;

  ErrorD_I = 0;
  //Variables de velocidad llanta derecha

  Conteo_Actual_D = 0;
  Conteo_D = 0;

  Pulsos_Min_D = 0; // OCR: "0O;" read as 0.
  RPM_Enc_D = 0;

  RPM_Mot_D = 0;
  Frecuencia_D = 0;

  //Variables de velocidad llanta izquierda

  Conteo_Actual_I = 0;
  Conteo_I = 0;

  Pulsos_Min_I = 0; // OCR: "O;" read as 0.
  RPM_Enc_I = 0;

  RPM_Mot_I = 0;
  Frecuencia_I = 0;

}

void leftEncoderEvent() { // Interrupcion para el encoder izquierdo
  if (digitalRead(LH_ENCODER_A) == HIGH) {
    if (digitalRead(LH_ENCODER_B) == LOW) {
      leftCount++;
    } else {
      leftCount--;
    }
  } else {
    if (digitalRead(LH_ENCODER_B) == LOW) { // OCR: "({" read as "{".
      leftCount--;
    } else {
      leftCount++;

    }
  }
  // OCR: the two closing braces of the else and the function are lost.
}

void rightEncoderEvent() { //Interrupcion para el encoder derecho
  if (digitalRead(RH_ENCODER_A) == HIGH) {
    if (digitalRead(RH_ENCODER_B) == LOW) {
      rightCount++;
    } else {
      rightCount--;

    }

  } else {

    if (digitalRead(RH_ENCODER_B) == LOW) { // OCR: "({" read as "{".
      rightCount--;

    } else {
      rightCount++;

    }

  }
}

void Nivel_Bateria() //determina el nivel de bateria

{
  Nivel = analogRead(A0); // OCR: "AQ" read as A0.
  //Serial.println (Nivel) ;

  if (Nivel > 942) {
    //azul

    analogWrite(ROJO, 0);

    analogWrite(VERDE, 0); // OCR: "O0" read as 0 (and below).

    analogWrite(AZUL, 255);
  }

  else if ((Nivel > 901) && (Nivel < 942)) { // OCR: "1f" read as "if" (and below).
    //verde
    analogWrite(ROJO, 0);
    analogWrite(VERDE, 255);

    analogWrite(AZUL, 0);
  }

  else if (Nivel < 901) {
    //rojo
    analogWrite(ROJO, 255);

    analogWrite(VERDE, 0);
    analogWrite(AZUL, 0);

  }
  // OCR: the closing braces of this branch and the function are lost.
}

void PID()// Controlador de los motores

{

  Nivel_Bateria();
  if (Flag_One == 1) {
    Tiempo_Actual = micros();
    Conteo_Actual_D = abs(rightCount);

    Conteo_Actual_I = abs(leftCount); // OCR: "Conteo_Actual:I" read as Conteo_Actual_I.
    Flag_One = 0;
  } // OCR: this "}" is lost (the block is read as ending here, as the port does).
  Tiempo_s = micros() - Tiempo_Actual;

  if (Tiempo_s >= 15000) {

    //** PARAMETROS DE VELOCIDAD DERECHA

    Conteo_D = abs(rightCount) - Conteo_Actual_D;

    Frecuencia_D = Conteo_D / (Tiempo_s / 1000000); //Pulsos por segundo
    Pulsos_Min_D = Frecuencia_D * 60; //Pulsos por minuto

    RPM_Enc_D = Pulsos_Min_D / 6; //Revoluciones por minuto del encoder
    RPM_Mot_D = abs(RPM_Enc_D) * (0.0016605);

    Serial.println(RPM_Mot_D);

    //** PARAMETROS DE VELOCIDAD IZQUIERDA

    Conteo_I = abs(leftCount) - Conteo_Actual_I;

    Frecuencia_I = Conteo_I / (Tiempo_s / 1000000); //Pulsos por segundo
    Pulsos_Min_I = Frecuencia_I * 60; //Pulsos por minuto

    RPM_Enc_I = Pulsos_Min_I / 6; //Revoluciones por minuto del encoder

    RPM_Mot_I = abs(RPM_Enc_I) * (0.0016605);
    Flag_One = 1; //Habilito bandera para reiniciar el conteo de los 15ms
    Serial.println(RPM_Mot_I);

    //**Controlador llanta derecha

    Error_D = (Set_D - RPM_Mot_D);
    Error_Pasado_D = Error_D * Muestreo + Error_Pasado_D;
    ErrorD_D = (Error_D - Error_Anterior_D) / Muestreo;

    // OCR: printed "PD=KpD * Error D; / D = Ki D * ... / D = Kd D * ... /
    // D=PD+ ID+ DD;" (the first letters lost); read as the P, I, D terms and
    // their sum U_D.
    P_D = Kp_D * Error_D;
    I_D = Ki_D * Error_Pasado_D;
    D_D = Kd_D * ErrorD_D;
    U_D = P_D + I_D + D_D;

    pwm_D = map(U_D, 24, -24, 255, 0);

    if (pwm_D >= 255) // Restriccionde PWM para evitar que suba a mas de 255
    { // OCR: this "{" is lost.
      pwm_D = 255;
    }
    else if (pwm_D <= 0)
    {
      pwm_D = 0;
    }

    //**Controlador llanta izquierda

    Error_I = (Set_I - RPM_Mot_I);
    Error_Pasado_I = Error_I * Muestreo + Error_Pasado_I;
    ErrorD_I = (Error_I - Error_Anterior_I) / Muestreo;

    // OCR: printed "PI=KpTI* Error I; / = Ki I * ... / = Kd I * ... /
    // =PI+ IT1I+DI;" (the left sides lost); read as the right wheel's.
    P_I = Kp_I * Error_I;
    I_I = Ki_I * Error_Pasado_I;
    D_I = Kd_I * ErrorD_I;
    U_I = P_I + I_I + D_I;

    pwm_I = map(U_I, 24, -24, 255, 0);
    Error_Anterior_D = Error_D; // OCR: "ErroriAnterioriD = Error Dy" read as this.
    Error_Anterior_I = Error_I;

    if (pwm_I >= 255) // Restriccionde PWM para evitar que suba a mas de 255
    {
      pwm_I = 255;
    }
    else if (pwm_I <= 0)
    {
      pwm_I = 0;
    }
  }
}
void Adelante()// Activa motores hacia adelante

{
  /// LLANTA DERECHA ADELANTE
  /// LLANTA IZQUIERDA ATRAS

  analogWrite(7, pwm_D);
  analogWrite(9, pwm_I);
  PID();
  // OCR: the closing brace is lost.
}

void Desplazamiento()

{

  //Calcula el desplazamiento

  DU_R = Constante * rightCount;
  DU_L = Constante * leftCount;
  DU_i = (DU_R + DU_L) / 2;

}

void Inercia_Stop_Ad()//Elimina la inercia

{

  analogWrite(7, 0); //Iguala a cero para desactivar pwm
  analogWrite(9, 0); //Iguala a cero para desactivar pwm
  delay(20);
  analogWrite(6, 255); //Activa pwm en sentido contrario
  analogWrite(8, 255); //Activa pwm en sentido contrario
  delay(5);
  analogWrite(6, 0); //Iguala a cero para desactivar pwm sentido contrario
  analogWrite(8, 0); //Iguala a cero para desactivar pwm sentido contrario
  delay(1000);
}
void Stop_General() //Detiene ambos motores

{

  analogWrite(6, 0); //LLANTA IZQUIERDA ADELANTE
  analogWrite(7, 0); //LLANTA IZQUIERDA ATRAS
  analogWrite(8, 0); //LLANTA DERECHA ADELANTE
  analogWrite(9, 0); //LLANTA DERECHA ATRAS
  delay(1000);

}

// OCR: the arguments of this function and the next are printed in columns
// apart from their calls ("analogWrite (7 / ... / 0); // ..."); read in
// order: the two inputs of the turn to 0, 20 ms, the other two at 255, 5 ms,
// those two to 0 ("Q)" read as "0)"), 1 s.
void Inercia_Stop_Izq()//Elimina la inercia

{
  analogWrite(7, 0); // LLANTA IZQUIERDA ATRAS
  analogWrite(8, 0); // LLANTA DERECHA ADELANTE
  delay(20);
  analogWrite(6, 255);
  analogWrite(9, 255);
  delay(5);
  analogWrite(6, 0);
  analogWrite(9, 0);
  delay(1000);
}

void Inercia_Stop_Der()//Elimina la inercia

{

  analogWrite(6, 0); // LLANTA IZQUIERDA ADELANTE
  analogWrite(9, 0); // LLANTA DERECHA ATRAS
  delay(20);
  analogWrite(7, 255);
  analogWrite(8, 255);
  delay(5);
  analogWrite(7, 0);
  analogWrite(8, 0);
  delay(1000);
}
